package rtaccel.traversal

import chisel3._
import chisel3.util._

/** One axis of a node in integer form: what every child lane of the node reads.
  * Distances are relative to the node's t0 in units u = 2^eu (GridNode).
  */
final case class GridAxisFixed(flat: Boolean, neg: Boolean, stepLo: BigInt, stepHi: BigInt, stepHiSat: Boolean,
    bLo: BigInt, bLoBelow: Boolean, bHi: BigInt, bHiAbove: Boolean, gHi: BigInt, gLo: BigInt)
final case class GridNodeFixed(axes: Seq[GridAxisFixed], tmin: BigInt, tmax: BigInt, err: Boolean)

class GridAxisHw(p: GridParams) extends Bundle {
  val flat      = Bool()
  val neg       = Bool()
  val stepLo    = UInt(p.stepBits.W)
  val stepHi    = UInt(p.stepBits.W)
  val stepHiSat = Bool()
  val bLo       = SInt(p.width.W)
  val bLoBelow  = Bool()
  val bHi       = SInt(p.width.W)
  val bHiAbove  = Bool()
  val gHi       = SInt(p.gBits.W)
  val gLo       = SInt(p.gBits.W)
}

class GridNodeHw(p: GridParams) extends Bundle {
  val axes = Vec(3, new GridAxisHw(p))
  val tmin = SInt(p.width.W)
  val tmax = SInt(p.width.W)
  val err  = Bool()
}

/** A child's box in its node's grid: plane offsets per axis (lo x, y, z; hi x, y, z). */
class GridChildHw(p: GridParams) extends Bundle {
  val qMin    = Vec(3, UInt(p.qBits.W))
  val qMax    = Vec(3, UInt(p.qBits.W))
  /** Used slot; an empty slot never hits. */
  val present = Bool()
}

/** The per-child half of the grid box test: per axis two products of a
  * qBits-bit offset and a step, two adds and a clamp, all in `width`-bit
  * integers; then the slab test's max/min and comparisons on integers
  * (docs/kernels.md, "Box tests in the node's grid", for why no child the
  * ray enters is missed). `near` is the child's entry distance relative to
  * the node (units of u): an order among siblings, not a distance.
  */
object GridLane {
  final case class Out(hit: Boolean, near: BigInt)

  def soft(p: GridParams, n: GridNodeFixed, qMin: Seq[Int], qMax: Seq[Int], present: Boolean): Out = {
    def clamp(v: BigInt) = v.max(p.bot).min(p.top)
    val axes = (0 until 3).map { i =>
      val a = n.axes(i)
      val (qe, qx) = if (a.neg) (p.qMax - qMax(i), p.qMax - qMin(i)) else (qMin(i), qMax(i))
      val lo = if (a.flat || a.bLoBelow) p.bot else clamp(a.bLo + qe * a.stepLo)
      val hi = if (a.flat || a.bHiAbove || (a.stepHiSat && qx != 0)) p.top else clamp(a.bHi + qx * a.stepHi)
      val in = !a.flat || (qe <= a.gHi && a.gLo <= qx)
      (lo, hi, in && qMin(i) <= qMax(i))
    }
    val near = axes.map(_._1).max
    val far = axes.map(_._2).min
    Out(present && !n.err && axes.forall(_._3) && near <= far && n.tmin <= far && near <= n.tmax, near)
  }
}

/** [[GridLane.soft]] in hardware: 3 cycles (products; sums and clamps;
  * max/min and comparisons), II = 1. Every register loads only on a valid
  * slot (the datapath's clock-enable rule, HwArith.ValidChain).
  */
class GridLane(p: GridParams) extends Module {
  val io = IO(new Bundle {
    val in   = Flipped(Valid(new Bundle {
      val node  = new GridNodeHw(p)
      val child = new GridChildHw(p)
    }))
    val hit  = Output(Bool())
    val near = Output(SInt(p.width.W))
    val outValid = Output(Bool())
  })
  override def desiredName = s"GridLane_${p.name}"
  val latency = 3
  private val v1 = RegNext(io.in.valid, false.B)
  private val v2 = RegNext(v1, false.B)
  io.outValid := RegNext(v2, false.B)

  private val n = io.in.bits.node
  private val c = io.in.bits.child
  private val qMaxU = p.qMax.U(p.qBits.W)
  // Cycle 1: offsets renumbered from the entry side, products.
  private val s1 = (0 until 3).map { i =>
    val a = n.axes(i)
    val qe = Mux(a.neg, qMaxU - c.qMax(i), c.qMin(i))
    val qx = Mux(a.neg, qMaxU - c.qMin(i), c.qMax(i))
    val en = io.in.valid
    (RegEnable(a, en), RegEnable(qe, en), RegEnable(qx, en), RegEnable(qe * a.stepLo, en), RegEnable(qx * a.stepHi, en),
      RegEnable(c.qMin(i) <= c.qMax(i), en))
  }
  private val err1 = RegEnable(n.err || !c.present, io.in.valid)
  private val tmin1 = RegEnable(n.tmin, io.in.valid)
  private val tmax1 = RegEnable(n.tmax, io.in.valid)
  private def clamp(v: SInt): SInt = Mux(v < p.bot.S, p.bot.S(p.width.W), Mux(v > p.top.S, p.top.S(p.width.W), v(p.width - 1, 0).asSInt))
  // Cycle 2: sums, clamps, the flat axes' origin test.
  private val s2 = s1.map { case (a, qe, qx, pLo, pHi, ok) =>
    val lo = Mux(a.flat || a.bLoBelow, p.bot.S(p.width.W), clamp(a.bLo +& pLo.zext))
    val hi = Mux(a.flat || a.bHiAbove || (a.stepHiSat && qx =/= 0.U), p.top.S(p.width.W), clamp(a.bHi +& pHi.zext))
    val in = !a.flat || (qe.zext <= a.gHi && a.gLo <= qx.zext)
    (RegEnable(lo, v1), RegEnable(hi, v1), RegEnable(in && ok, v1))
  }
  private val err2 = RegEnable(err1, v1)
  private val tmin2 = RegEnable(tmin1, v1)
  private val tmax2 = RegEnable(tmax1, v1)
  // Cycle 3: the slab test on integers.
  private def max2(a: SInt, b: SInt) = Mux(a < b, b, a)
  private def min2(a: SInt, b: SInt) = Mux(a < b, a, b)
  private val near = s2.map(_._1).reduce(max2)
  private val far = s2.map(_._2).reduce(min2)
  private val hit = !err2 && s2.map(_._3).reduce(_ && _) && near <= far && tmin2 <= far && near <= tmax2
  io.hit := RegEnable(hit, v2)
  io.near := RegEnable(near, v2)
}
