package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.datapath._
import rtaccel.fp.FloatFormat

/** The per-node half of the grid box test in integer form: [[GridKernel]]'s
  * outward bounds, turned into `width`-bit integers in units of u = 2^eu,
  * rounded outward again (floor for a lower bound, ceil for an upper one) and
  * clamped to the window (docs/kernels.md, "Box tests in the node's grid").
  *
  * u: the smallest grid step in t over the non-flat axes is 2^s R- >= 2^eS
  * with eS = exponent(R-) + s, so u = 2^(eS - fracBits) is 1/2^fracBits to
  * 1/2^(fracBits+1) of it. Any eu keeps the test conservative; this one keeps
  * a child's slab ends to within u of the exact ones.
  */
object GridNode {

  /** qMax 2^s in `fmt` (exact: s must be in the format's normal range). */
  def spanSoft(fmt: FloatFormat, p: GridParams, s: Int): BigInt = {
    require(p.qBits - 1 <= fmt.manBits, s"GridNode: qBits ${p.qBits} too wide for $fmt")
    fmt.pack(false, s + fmt.bias + p.qBits - 1, (BigInt(1) << (p.qBits - 1)) - 1 << (fmt.manBits - p.qBits + 1))
  }

  /** The unit's exponent: min over non-flat axes of exponent(R-) + s, less fracBits (0 if all are flat). */
  def euSoft(fmt: FloatFormat, p: GridParams, flat: Seq[Boolean], rcpLo: Seq[BigInt], s: Seq[Int]): Int = {
    val es = (0 until 3).filterNot(flat).map(i => math.max(fmt.expField(rcpLo(i)), 1) - fmt.bias + s(i))
    if (es.isEmpty) 0 else es.min - p.fracBits
  }

  def soft(
      fmt: FloatFormat,
      p: GridParams,
      ray: RayK[BigInt, Boolean],
      tmax: BigInt,
      origin: Seq[BigInt],
      s: Seq[Int]
  ): GridNodeFixed = {
    val ar = new GoldenArith(fmt)
    val k = GridKernel(ar, ray, tmax, origin, s.map(spanSoft(fmt, p, _)))
    val eu = euSoft(fmt, p, k.axes.map(_.flat), ray.rcpLo, s)
    def fx(x: BigInt, sh: Int, up: Boolean, lo: BigInt, hi: BigInt) = GridFixed.soft(fmt, x, sh, up, lo, hi)
    val axes = k.axes.zipWithIndex.map { case (a, i) =>
      val sLo = fx(ray.rcpLo(i), s(i) - eu, up = false, 0, p.stepMax)
      val sHi = fx(ray.rcpHi(i), s(i) - eu, up = true, 0, p.stepMax)
      val cLo = fx(a.cLo, p.cFracBits - s(i), up = false, p.cLo, p.cHi)
      val cHi = fx(a.cHi, p.cFracBits - s(i), up = true, p.cLo, p.cHi)
      val gHi = fx(fmt.negate(a.diffLo), -s(i), up = false, p.gLo, p.gHi)
      val gLo = fx(fmt.negate(a.diffHi), -s(i), up = true, p.gLo, p.gHi)
      GridAxisFixed(
        a.flat,
        a.neg,
        sLo.value,
        sHi.value,
        sHi.above,
        cLo.value,
        cLo.below,
        cHi.value,
        cHi.above,
        gHi.value,
        gLo.value
      )
    }
    GridNodeFixed(
      axes,
      fx(k.tminR, -eu, up = false, p.bot, p.top).value,
      fx(k.tmaxR, -eu, up = true, p.bot, p.top).value,
      k.err
    )
  }
}

/** What the per-node stage reads: the ray's constants and tmax, and the node's
  * per-axis origin and scale exponent as the 4q/8q record holds them (QuantNode).
  */
class GridNodeIn(rays: RayConsts) extends Bundle {
  val ray = rays.cloneType

  /** In the triangle format; rounded up to FP32 where that is narrower (BoxKernel.narrowTmax). */
  val tmax = UInt(rays.triFmt.width.W)
  val origin = Vec(3, UInt(32.W))

  /** Scale exponent fields e (scale 2^(e-127)), QuantNode.ExpMin..ExpMax. */
  val exp = Vec(3, UInt(8.W))
}

/** [[GridNode.soft]] in hardware: the FP32 [[GridKernel]] pipeline (HwArith
  * units, each enabled by the slot's valid), then six cycles of
  * conversions (GridFixed.examine, sums, decide, front, back and clamp, a register after each).
  * `out` is valid `latency` cycles after `in`.
  */
class GridNodeStage(p: GridParams, rays: RayConsts) extends Module with ValidChains {
  private val fmt = rays.boxFmt
  require(
    fmt == FloatFormat.FP32,
    s"GridNodeStage: the node's planes are FP32; the box constants must be too, not $fmt"
  )
  val io = IO(new Bundle {
    val in = Flipped(Valid(new GridNodeIn(rays)))
    val out = Valid(new GridNodeHw(p))

    /** A scale exponent outside QuantNode.ExpMin..ExpMax: bad scene data; no child hits. */
    val badScale = Output(Bool())
  })
  override def desiredName = s"GridNodeStage_${p.name}"

  private val chain = validChain(io.in.valid)
  private val ar = new HwArith(fmt, chain)
  private val ray = RayConsts.readBox(ar, io.in.bits.ray)
  private val tmax = BoxKernel.narrowTmax(ar, BoxRounding.Conservative, ar.input(io.in.bits.tmax), rays.triFmt)
  private val e = io.in.bits.exp
  private val bad = e.map(x => x < rtaccel.bvh.QuantNode.ExpMin.U || x > rtaccel.bvh.QuantNode.ExpMax.U).reduce(_ || _)
  // qMax 2^s: exponent field e + qBits - 1, the qBits - 1 fraction bits below the point set. Registered (cut)
  // before the adder: the exponent's add in front of the adder's first stage was the unit's longest path.
  private val span = e.map(x =>
    ar.cut(ar.input(Cat(
      0.U(1.W),
      x + (p.qBits - 1).U,
      ((BigInt(1) << (p.qBits - 1)) - 1).U((p.qBits - 1).W),
      0.U((fmt.manBits - p.qBits + 1).W)
    )))
  )
  private val k = GridKernel(ar, ray, tmax, io.in.bits.origin.map(ar.input), span)

  // The unit's exponent at cycle 0 (inputs only), delayed with the rest.
  private val sInt = e.map(x => x.zext - 127.S)
  private val flat0 = io.in.bits.ray.box.dir.map(d => d(fmt.width - 2, 0) === 0.U)
  private val es = (0 until 3).map { i =>
    val ef = io.in.bits.ray.box.rcpLo.get(i)(fmt.width - 2, fmt.manBits)
    Mux(ef === 0.U, 1.U, ef).zext - fmt.bias.S + sInt(i)
  }
  private val big = (1 << 11).S
  private def timed[T <: Data](x: T) = new Timed(x, 0, chain)
  // One carry chain per cycle (each a register apart): the exponents (cycle 0),
  // the least of two (1), of three (2), less fracBits (3). eu is read at c - 1.
  private def next[T <: Data](x: T, t: Int) = new Timed(x, t, chain).at(t + 1)
  private val es1 = (0 until 3).map(i => next(Mux(flat0(i), big, es(i)), 0))
  private def min(a: SInt, b: SInt) = Mux(a < b, a, b)
  private val es2 = next(min(es1(0), es1(1)), 1)
  private val es3 = next(min(es2, next(es1(2), 1)), 2)
  private val eu = new Timed(Mux(timed(flat0.reduce(_ && _)).at(3), 0.S, es3 - p.fracBits.S), 3, chain)

  val latency: Int =
    (k.axes.flatMap(a => Seq(a.cLo, a.cHi, a.diffLo, a.diffHi)) ++ Seq(k.tminR, k.tmaxR)).map(_.ready).max + 6
  // The conversions: examine in cycle c, sums in c + 1, decide in c + 2, front in c + 3, back in c + 4, clamp in
  // c + 5.
  private val c = latency - 6
  // The conversions' shifts, prepared ahead (GridFixed.shift) and registered for decide.
  private val euP = eu.at(c - 1)
  private val sP = sInt.map(timed(_).at(c - 1))
  private def shift(k: SInt, lo: BigInt, hi: BigInt) =
    new Timed(GridFixed.shift(fmt, k, lo, hi), c - 1, chain).at(c + 2)
  private val rcpLoC = ray.rcpLo.map(_.at(c))
  private val rcpHiC = ray.rcpHi.map(_.at(c))
  private def fx(x: UInt, sh: GridFixed.Shift, up: Boolean, lo: BigInt, hi: BigInt) = {
    val ex = new Timed(GridFixed.examine(fmt, x), c, chain).at(c + 1)
    val su = new Timed(GridFixed.sums(fmt, ex), c + 1, chain).at(c + 2)
    val d = new Timed(GridFixed.decide(fmt, su, sh, up, lo, hi), c + 2, chain).at(c + 3)
    val b = GridFixed.back(new Timed(GridFixed.front(d, lo, hi), c + 3, chain).at(c + 4), up, lo, hi)
    GridFixed.clamp(new Timed(b, c + 4, chain).at(c + 5), up, lo, hi)
  }
  private def negF(x: UInt) = Cat(!x(fmt.width - 1), x(fmt.width - 2, 0))
  private val node = Wire(new GridNodeHw(p))
  for (i <- 0 until 3) {
    val a = k.axes(i)
    val o = node.axes(i)
    val kS = shift(sP(i) - euP, 0, p.stepMax)
    val kC = shift(p.cFracBits.S - sP(i), p.cLo, p.cHi)
    val kG = shift(-sP(i), p.gLo, p.gHi)
    val sLo = fx(rcpLoC(i), kS, up = false, 0, p.stepMax)
    val sHi = fx(rcpHiC(i), kS, up = true, 0, p.stepMax)
    val cLo = fx(a.cLo.at(c), kC, up = false, p.cLo, p.cHi)
    val cHi = fx(a.cHi.at(c), kC, up = true, p.cLo, p.cHi)
    o.flat := a.flat.at(c + 5)
    o.neg := a.neg.at(c + 5)
    o.stepLo := sLo.value.asUInt(p.stepBits - 1, 0)
    o.stepHi := sHi.value.asUInt(p.stepBits - 1, 0)
    o.stepHiSat := sHi.above
    o.cLo := cLo.value
    o.cLoBelow := cLo.below
    o.cHi := cHi.value
    o.cHiAbove := cHi.above
    o.gHi := fx(negF(a.diffLo.at(c)), kG, up = false, p.gLo, p.gHi).value
    o.gLo := fx(negF(a.diffHi.at(c)), kG, up = true, p.gLo, p.gHi).value
  }
  private val kT = shift(-euP, p.bot, p.top)
  node.tmin := fx(k.tminR.at(c), kT, up = false, p.bot, p.top).value(p.width - 1, 0).asSInt
  node.tmax := fx(k.tmaxR.at(c), kT, up = true, p.bot, p.top).value(p.width - 1, 0).asSInt
  node.err := k.err.at(c + 5)
  io.out.valid := chain.at(latency)
  io.out.bits := RegEnable(node, chain.at(c + 5))
  io.badScale := timed(bad).at(latency)
}
