package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.datapath.{Timed, ValidChains}

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

/** [[GridLane.soft]] in hardware: 5 cycles (distances and their signs; step selects; products; sums and clamps;
  * max/min and comparisons), II = 1. Every register loads only on a valid slot (the datapath's clock-enable rule,
  * HwArith.ValidChain).
  */
class GridLane(p: GridParams) extends Module with ValidChains {
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
  val latency = 5
  private val chain = validChain(io.in.valid)
  private val Seq(v1, v2, v3, v4) = (1 to 4).map(chain.at)
  io.outValid := chain.at(latency)

  private val n = io.in.bits.node
  private val c = io.in.bits.child
  // What only the last cycle reads, carried to it.
  private def toLast[T <: Data](x: T): T = new Timed(x, 0, chain).at(4)
  private val (err, tmin, tmax) = (toLast(n.err || !c.present), toLast(n.tmin), toLast(n.tmax))
  // The multiply is unsigned, as Yosys packs it into one DSP48E1 (a signed product, which the Verilog writes
  // with sign-extended operands, would take two). A distance d of dBits bits is biased into an unsigned
  // a = d + 2^(dBits-1) (its sign bit inverted, no logic), and the post-adder's C input takes the bias back:
  // a step + C = d step + r with C = -(step 2^(dBits-1)) + r, r the round-up's 2^f - 1 for an upper bound (0
  // for a lower one; an OR, since -(step 2^(dBits-1)) has dBits - 1 low zero bits and r < 2^f <= 2^(dBits-1)).
  private val bias = p.dBits - 1
  private val f = p.cFracBits
  require(f <= bias, s"GridLane: cFracBits $f above the distance's bias $bias")
  private def biased(d: SInt) = Cat(!d(p.dBits - 1), d(p.dBits - 2, 0))

  // Cycle 1: offsets renumbered from the entry side and their distances from c: per distance, a LUT (qMax - q
  // is ~q, qMax = 2^qBits - 1) and a subtraction, nothing after it.
  private val s0 = (0 until 3).map { i =>
    val a = n.axes(i)
    val qe = Mux(a.neg, ~c.qMax(i), c.qMin(i))
    val qx = Mux(a.neg, ~c.qMin(i), c.qMax(i))
    // dBits holds every q' - c (GridParams.dBits): the low bits are the exact difference.
    val dLo = ((qe << p.cFracBits).zext - a.cHi)(p.dBits - 1, 0).asSInt
    val dHi = ((qx << p.cFracBits).zext - a.cLo)(p.dBits - 1, 0).asSInt
    val en = chain.at(0)
    val in = !a.flat || (qe.zext <= a.gHi && a.gLo <= qx.zext)
    (
      (RegEnable(biased(dLo), en), RegEnable(biased(dHi), en)),
      (RegEnable(a.stepLo, en), RegEnable(a.stepHi, en), RegEnable(a.stepHiSat, en)),
      (
        RegEnable(a.flat || a.cHiAbove, en),
        RegEnable(a.flat || a.cLoBelow, en),
        RegEnable(in && c.qMin(i) <= c.qMax(i), en)
      )
    )
  }
  // Cycle 2: each product's operands (the lower step for a lower bound of a positive product, the upper one
  // otherwise) into registers: the DSP48E1's A, B and C registers, so that the multiply has no fabric logic in
  // its cycle (docs/fmax.md, Method: a DSP48E1 is timed as a register only when its multiply sits between
  // registers). A distance's sign is read from its biased form (negative: the top bit clear; positive: the
  // top bit set and another); the steps' negations are formed beside it.
  private def cOf(negStep: SInt, up: Boolean) = {
    val c = (negStep << bias).asSInt
    if (up) (c.asUInt | ((1 << f) - 1).U).asSInt else c
  }
  private val s1 = s0.map { case ((aLo, aHi), (stepLo, stepHi, sat), (loFlag, hiFlag, ok)) =>
    val loNeg = !aLo(bias)
    val hiPos = aHi(bias) && aHi(bias - 1, 0).orR
    val (negLo, negHi) = (-(stepLo.zext), -(stepHi.zext))
    (
      (
        RegEnable(aLo, v1),
        RegEnable(Mux(loNeg, stepHi, stepLo), v1),
        RegEnable(cOf(Mux(loNeg, negHi, negLo), up = false), v1)
      ),
      (
        RegEnable(aHi, v1),
        RegEnable(Mux(hiPos, stepHi, stepLo), v1),
        RegEnable(cOf(Mux(hiPos, negHi, negLo), up = true), v1)
      ),
      (RegEnable(loFlag || (loNeg && sat), v1), RegEnable(hiFlag || (hiPos && sat), v1), RegEnable(ok, v1))
    )
  }
  // Cycle 3: the products (dBits x stepBits unsigned) and their post-adds, one DSP48E1 each, into its P register:
  // d step for a lower bound, d step + 2^f - 1 for an upper one.
  private def dsp(ops: (UInt, UInt, SInt)) = RegEnable((ops._1 * ops._2).zext + ops._3, v2)
  private val prods = s1.map { case (lo, hi, (loOut, hiOut, ok)) =>
    (dsp(lo), dsp(hi), RegEnable(loOut, v2), RegEnable(hiOut, v2), RegEnable(ok, v2))
  }
  // Cycle 4: outward to units of u, v / 2^f rounded down (an arithmetic shift of v) or up (of v + 2^f - 1, formed
  // in the DSP; the model's -((-v) >> f) is the same integer), then clamped. The clamp compares the DSP's sum
  // itself with the window's ends scaled by 2^f: the rounded value is past top iff v > top 2^f (up) or
  // v >= (top + 1) 2^f (down), and past bot iff v <= (bot - 1) 2^f (up) or v < bot 2^f (down).
  private def outward(sum: SInt, up: Boolean): SInt = {
    val r = if (up) (1 << f) - 1 else 0
    val q = (sum >> f).asSInt
    val below = if (up) sum <= (((p.bot - 1) << f) + r).S else sum < (p.bot << f).S
    val above = if (up) sum > ((p.top << f) + r).S else sum >= ((p.top + 1) << f).S
    Mux(below, p.bot.S(p.width.W), Mux(above, p.top.S(p.width.W), q(p.width - 1, 0).asSInt))
  }
  private val s2 = prods.map { case (pLo, pHi, loOut, hiOut, ok) =>
    val lo = Mux(loOut, p.bot.S(p.width.W), outward(pLo, up = false))
    val hi = Mux(hiOut, p.top.S(p.width.W), outward(pHi, up = true))
    (RegEnable(lo, v3), RegEnable(hi, v3), RegEnable(ok, v3))
  }
  // Cycle 5: the slab test on integers. near <= far, tmin <= far and near <= tmax, with near the largest lo and
  // far the least hi, hold exactly when every lo is at most every hi and tmax, and tmin at most every hi: 15
  // compares side by side, where the max and min in front of the compares were the lane's longest path.
  private val los = s2.map(_._1)
  private val his = s2.map(_._2)
  private val ordered = (for (lo <- los; hi <- his) yield lo <= hi) ++ los.map(_ <= tmax) ++ his.map(tmin <= _)
  private val hit = !err && s2.map(_._3).reduce(_ && _) && ordered.reduce(_ && _)
  // near (the largest lo) from the three pairwise compares at once, not two compares in a row.
  private val ge01 = los(0) >= los(1)
  private val ge02 = los(0) >= los(2)
  private val ge12 = los(1) >= los(2)
  private val near = Mux(ge01 && ge02, los(0), Mux(!ge01 && ge12, los(1), los(2)))
  io.hit := RegEnable(hit, v4)
  io.near := RegEnable(near, v4)
}
