package rtaccel.traversal

import chisel3._
import chisel3.util._

/** One axis of a node in integer form: what every child lane of the node reads.
  * Steps are in units u = 2^eu of t (GridNode); cLo..cHi bound the ray's grid
  * coordinate at t0 in units of 2^-cFracBits (`cLoBelow`/`cHiAbove`: past the window).
  */
final case class GridAxisFixed(
    flat: Boolean,
    neg: Boolean,
    stepLo: BigInt,
    stepHi: BigInt,
    stepHiSat: Boolean,
    cLo: BigInt,
    cLoBelow: Boolean,
    cHi: BigInt,
    cHiAbove: Boolean,
    gHi: BigInt,
    gLo: BigInt
)
final case class GridNodeFixed(axes: Seq[GridAxisFixed], tmin: BigInt, tmax: BigInt, err: Boolean)

class GridAxisHw(p: GridParams) extends Bundle {
  val flat = Bool()
  val neg = Bool()
  val stepLo = UInt(p.stepBits.W)
  val stepHi = UInt(p.stepBits.W)
  val stepHiSat = Bool()
  val cLo = SInt(p.cBits.W)
  val cLoBelow = Bool()
  val cHi = SInt(p.cBits.W)
  val cHiAbove = Bool()
  val gHi = SInt(p.gBits.W)
  val gLo = SInt(p.gBits.W)
}

class GridNodeHw(p: GridParams) extends Bundle {
  val axes = Vec(3, new GridAxisHw(p))
  val tmin = SInt(p.width.W)
  val tmax = SInt(p.width.W)
  val err = Bool()
}

/** A child's box in its node's grid: plane offsets per axis (lo x, y, z; hi x, y, z). */
class GridChildHw(p: GridParams) extends Bundle {
  val qMin = Vec(3, UInt(p.qBits.W))
  val qMax = Vec(3, UInt(p.qBits.W))

  /** Used slot; an empty slot never hits. */
  val present = Bool()
}

/** The per-child half of the grid box test: per axis the offsets' distance
  * from the ray's grid coordinate (q' - c, one subtraction each) times a step
  * (the lower step for a lower bound of a positive product, the upper one
  * otherwise), rounded outward to units of u and clamped to `width` bits; then the slab test's max/min and comparisons on integers
  * (docs/kernels.md, "Box tests in the node's grid", for why no child the
  * ray enters is missed). `near` is the child's entry distance relative to
  * the node (units of u): an order among siblings, not a distance.
  */
object GridLane {
  final case class Out(hit: Boolean, near: BigInt)

  def soft(p: GridParams, n: GridNodeFixed, qMin: Seq[Int], qMax: Seq[Int], present: Boolean): Out = {
    def clamp(v: BigInt) = v.max(p.bot).min(p.top)
    def floorDiv(v: BigInt) = v >> p.cFracBits // arithmetic: floor
    def ceilDiv(v: BigInt) = -((-v) >> p.cFracBits)
    val axes = (0 until 3).map { i =>
      val a = n.axes(i)
      val (qe, qx) = if (a.neg) (p.qMax - qMax(i), p.qMax - qMin(i)) else (qMin(i), qMax(i))
      val dLo = (BigInt(qe) << p.cFracBits) - a.cHi // <= qe - c
      val dHi = (BigInt(qx) << p.cFracBits) - a.cLo // >= qx - c
      val lo = if (a.flat || a.cHiAbove || (dLo < 0 && a.stepHiSat)) p.bot
      else clamp(floorDiv(dLo * (if (dLo >= 0) a.stepLo else a.stepHi)))
      val hi = if (a.flat || a.cLoBelow || (dHi > 0 && a.stepHiSat)) p.top
      else clamp(ceilDiv(dHi * (if (dHi > 0) a.stepHi else a.stepLo)))
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
    val in = Flipped(Valid(new Bundle {
      val node = new GridNodeHw(p)
      val child = new GridChildHw(p)
    }))
    val hit = Output(Bool())
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
  // Cycle 1: offsets renumbered from the entry side, their distances from c, products. qMax - q is ~q
  // (qMax = 2^qBits - 1), no carry chain; each distance's sign is a compare of its operands, beside the
  // subtraction, so the step it picks for the multiplier does not wait on the difference.
  private val s1 = (0 until 3).map { i =>
    val a = n.axes(i)
    val qe = Mux(a.neg, ~c.qMax(i), c.qMin(i))
    val qx = Mux(a.neg, ~c.qMin(i), c.qMax(i))
    val qeF = (qe << p.cFracBits).zext
    val qxF = (qx << p.cFracBits).zext
    val dLo = qeF - a.cHi
    val dHi = qxF - a.cLo
    val dLoNeg = qeF < a.cHi
    val dHiPos = qxF > a.cLo
    val en = io.in.valid
    val pLo = dLo * Mux(dLoNeg, a.stepHi, a.stepLo).zext
    val pHi = dHi * Mux(dHiPos, a.stepHi, a.stepLo).zext
    val loOut = a.flat || a.cHiAbove || (dLoNeg && a.stepHiSat)
    val hiOut = a.flat || a.cLoBelow || (dHiPos && a.stepHiSat)
    val in = !a.flat || (qe.zext <= a.gHi && a.gLo <= qx.zext)
    (
      RegEnable(pLo, en),
      RegEnable(pHi, en),
      RegEnable(loOut, en),
      RegEnable(hiOut, en),
      RegEnable(in && c.qMin(i) <= c.qMax(i), en)
    )
  }
  private val err1 = RegEnable(n.err || !c.present, io.in.valid)
  private val tmin1 = RegEnable(n.tmin, io.in.valid)
  private val tmax1 = RegEnable(n.tmax, io.in.valid)
  // Cycle 2: outward to units of u, v / 2^f rounded down (an arithmetic shift) or up ((v + 2^f - 1) >> f, one add;
  // the model's -((-v) >> f) is the same integer), then clamped. The clamp compares v itself with the window's
  // ends scaled by 2^f, beside the add: the rounded value is past top iff v > top 2^f (up) or v >= (top + 1) 2^f
  // (down), and past bot iff v <= (bot - 1) 2^f (up) or v < bot 2^f (down).
  private def outward(v: SInt, up: Boolean): SInt = {
    val f = p.cFracBits
    val q = ((if (up) v +& ((1 << f) - 1).S else v) >> f).asSInt
    val below = if (up) v <= ((p.bot - 1) << f).S else v < (p.bot << f).S
    val above = if (up) v > (p.top << f).S else v >= ((p.top + 1) << f).S
    Mux(below, p.bot.S(p.width.W), Mux(above, p.top.S(p.width.W), q(p.width - 1, 0).asSInt))
  }
  private val s2 = s1.map { case (pLo, pHi, loOut, hiOut, ok) =>
    val lo = Mux(loOut, p.bot.S(p.width.W), outward(pLo, up = false))
    val hi = Mux(hiOut, p.top.S(p.width.W), outward(pHi, up = true))
    (RegEnable(lo, v1), RegEnable(hi, v1), RegEnable(ok, v1))
  }
  private val err2 = RegEnable(err1, v1)
  private val tmin2 = RegEnable(tmin1, v1)
  private val tmax2 = RegEnable(tmax1, v1)
  // Cycle 3: the slab test on integers. near <= far, tmin <= far and near <= tmax, with near the largest lo and
  // far the least hi, hold exactly when every lo is at most every hi and tmax, and tmin at most every hi: 15
  // compares side by side, where the max and min in front of the compares were the lane's longest path.
  private val los = s2.map(_._1)
  private val his = s2.map(_._2)
  private val ordered = (for (lo <- los; hi <- his) yield lo <= hi) ++ los.map(_ <= tmax2) ++ his.map(tmin2 <= _)
  private val hit = !err2 && s2.map(_._3).reduce(_ && _) && ordered.reduce(_ && _)
  // near (the largest lo) from the three pairwise compares at once, not two compares in a row.
  private val ge01 = los(0) >= los(1)
  private val ge02 = los(0) >= los(2)
  private val ge12 = los(1) >= los(2)
  private val near = Mux(ge01 && ge02, los(0), Mux(!ge01 && ge12, los(1), los(2)))
  io.hit := RegEnable(hit, v2)
  io.near := RegEnable(near, v2)
}
