package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point adder (or subtractor, with `subtract`): `a + b` (`a - b`)
  * rounded once in the mode. Front: compare the magnitudes and swap; align
  * the smaller significand with guard/round/sticky bits; add or subtract;
  * then [[FpRound]]. Cut points ([[FpPipeline]]): after the swap, after the
  * alignment, after the add, the rounder's, and the output; the default
  * latency puts one register on each.
  *
  * @param rm      Some(mode) fixes the mode at elaboration; None adds an `rm` input
  * @param latency cycles from `in` to `out`
  */
class FpAdd(
    val fmt: FloatFormat,
    val rm: Option[RoundingMode],
    val latency: Int = FpAdd.defaultLatency,
    val subtract: Boolean = false
) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name(if (subtract) "FpSub" else "FpAdd", fmt, rm, latency)

  private val pipe = new FpPipeline(latency, FpAdd.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpAdd.front(fmt, io.in.bits, subtract, stages, r => Seq(FpUnitIO.roundingMode(rm, r))))
  private val rounded = FpRound.inModes(
    fmt,
    mid.raw,
    Seq((FpUnitIO.roundingMode(rm, mid.rm), mid.signs(0))),
    Some(FpAdd.minExp(fmt)),
    Some(stages)
  ).head
  io.out := pipe.cut(stages.valid, rounded)
  pipe.done()
}

/** [[FpAdd]] (or its subtractor) rounded both down (RDN) and up (RUP) from
  * one exact sum: one front and normaliser, two final roundings
  * (FpRound.inModes). Each result is bit for bit the single-mode unit's
  * (an exact zero's sign included); same cuts and latency.
  */
class FpAddDnUp(val fmt: FloatFormat, val latency: Int = FpAdd.defaultLatency, val subtract: Boolean = false)
    extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, false), new FpDnUp(fmt)))
  override def desiredName: String = s"${if (subtract) "FpSub" else "FpAdd"}DnUp_${fmt.name}_l$latency"

  private val modes = Seq(RoundingMode.RDN, RoundingMode.RUP).map(_.code.U(RoundingMode.width.W))
  private val pipe = new FpPipeline(latency, FpAdd.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpAdd.front(fmt, io.in.bits, subtract, stages, _ => modes))
  private val rounded =
    FpRound.inModes(fmt, mid.raw, modes.zip(mid.signs), Some(FpAdd.minExp(fmt)), Some(stages))
  io.out := pipe.cut(stages.valid, FpDnUp(fmt, rounded))
  pipe.done()
}

/** The adder front's state between its cuts. */
class FpAddFront(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  private val p = fmt.precision
  val big = new FpUnpacked(fmt)
  val smallSig = UInt(p.W)
  val dist = UInt((fmt.expBits + 1).W)
  val effSub = Bool()
  val isNaN = Bool()
  val isInf = Bool()
  val infSign = Bool()
  val smallAligned = UInt((p + FpAdd.extra).W)
  val sticky = Bool()
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}

/** The adder's exact sum before rounding, with the result's sign in each mode
  * (they differ only for an exact zero from x + (-x)).
  */
class FpAddMid(sigWidth: Int, expWidth: Int, dynamicRm: Boolean, modes: Int) extends Bundle {
  val raw = new FpRaw(sigWidth, expWidth)
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
  val signs = Vec(modes, Bool())
}

object FpAdd {

  /** Guard, round and sticky positions below the aligned LSB. Two would do
    * (FpRaw needs precision+1 bits when sticky; an effective subtraction with
    * d > extra loses at most one leading bit); three keeps a margin.
    */
  val extra: Int = 3

  /** The front: swap, align, add (three cuts of `stages`), up to the
    * rounder's input, for the modes `modesOf` gives from the carried runtime
    * mode (if any).
    */
  def front(
      fmt: FloatFormat,
      in: FpBinaryIn,
      subtract: Boolean,
      stages: FpStages,
      modesOf: Option[UInt] => Seq[UInt]
  ): FpAddMid = {
    val p = fmt.precision
    val extra = FpAdd.extra
    val sw = p + extra
    val ew = FpUnpack.expWidth(fmt)

    val ua = FpUnpack(fmt, in.a)
    val ub0 = FpUnpack(fmt, in.b)
    val ub = WireInit(ub0)
    if (subtract) ub.sign := !ub0.sign // exact; NaN signs do not matter (canonical NaN out)

    val dynamicRm = in.rm.isDefined

    // Cut 1: swap by exponent. Both operands' LSB exponents carry the same
    // offset from their (subnormal-adjusted) fields, so fields are compared and
    // subtracted directly, both ways at once: no chain waits on another.
    val f0 = Wire(new FpAddFront(fmt, dynamicRm))
    f0 := DontCare
    f0.rm.foreach(_ := in.rm.get)
    // |a| >= |b|, compared as the magnitudes' bit patterns (IEEE magnitudes order as integers, subnormals
    // included), so the exponents are in order and, when they are equal, the significands too: a
    // difference is never negative, and the add stage needs no second chain for its negation nor a select
    // behind its carry chain (docs/fmax.md). NaNs compare arbitrarily; they leave as the canonical NaN.
    val aBig = in.a(fmt.width - 2, 0) >= in.b(fmt.width - 2, 0)
    val big = Mux(aBig, ua, ub)
    f0.big := big
    f0.smallSig := Mux(aBig, ub.sig, ua.sig)
    // dist = big.exp - small.exp >= 0, from the raw fields: a subnormal's field 0 stands for 1, so when only
    // the smaller operand is subnormal the field difference is one too big. Both candidates are chains on
    // the raw fields, picked after them (with the subnormal fix in front of each chain, 5.05 ns).
    val (ea, eb) = (in.a(fmt.width - 2, fmt.manBits), in.b(fmt.width - 2, fmt.manBits))
    val (eaZero, ebZero) = (ea === 0.U, eb === 0.U)
    def less1(x: UInt, y: UInt): UInt = (x +& ~y)(fmt.expBits - 1, 0) // x - y - 1 when x > y
    f0.dist := Mux(
      aBig,
      Mux(ebZero && !eaZero, less1(ea, eb), ea -& eb),
      Mux(eaZero && !ebZero, less1(eb, ea), eb -& ea)
    )
    f0.effSub := ua.sign =/= ub.sign
    f0.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isInf && f0.effSub)
    f0.isInf := ua.isInf || ub.isInf
    f0.infSign := Mux(ua.isInf, ua.sign, ub.sign)
    val f1 = stages(f0)

    // Cut 2: align the smaller significand (its sticky bit beside the shifter).
    val f2 = Wire(new FpAddFront(fmt, dynamicRm))
    f2 := f1
    val (smallAligned, sticky) = FpUnpack.shiftRightSticky(Cat(f1.smallSig, 0.U(extra.W)), f1.dist)
    f2.smallAligned := smallAligned
    f2.sticky := sticky
    val f3 = stages(f2)

    // Cut 3: add or subtract. A true difference is big - (smallAligned + d),
    // d in (0,1) when sticky: = (big - smallAligned - 1) + (1 - d), so subtract
    // the sticky bit too. big >= smallAligned + sticky (the swap, and sticky needs the exponents apart), so
    // the difference is never negative: big + ~smallAligned + !sticky, the sticky's borrow as the chain's carry
    // in (an extra low bit: 1 + !sticky carries exactly !sticky), one two-operand chain.
    //
    // Timing (docs/fmax.md): the carry chains feed only the final mux, and the exact-zero test, which the
    // result's sign waits on, reads the operands beside the chains, not their result.
    val bigExt = Cat(f3.big.sig, 0.U(extra.W))
    val diff = (Cat(bigExt, 1.U(1.W)) + Cat(~f3.smallAligned, !f3.sticky))(sw, 1)
    val mag = Mux(f3.effSub, diff, bigExt +& f3.smallAligned)
    // mag === 0, from the operands. A difference with sticky set is never 0: sticky needs the
    // exponents extra + 1 or more apart, so big is normal, bigExt >= 2^(p + extra - 1) and
    // smallAligned < 2^(p - 1). Without sticky it is 0 exactly when the aligned significands
    // are equal. A sum is 0 exactly when both are.
    val magZero = Mux(
      f3.effSub,
      !f3.sticky && bigExt === f3.smallAligned,
      f3.big.sig === 0.U && f3.smallAligned === 0.U
    )

    val modes = modesOf(f3.rm)
    val front = Wire(new FpAddMid(sw + 1, ew + 1, dynamicRm, modes.size))
    val raw = front.raw
    front.rm.foreach(_ := f3.rm.get)
    raw.isNaN := f3.isNaN
    raw.isInf := f3.isInf
    // Exact zero: (-0)+(-0) = -0, x+(-x) = +0 except -0 in RDN (IEEE 754 6.3).
    raw.isZero := magZero && !f3.sticky
    for ((m, j) <- modes.zipWithIndex)
      front.signs(j) := MuxCase(
        f3.big.sign,
        Seq(f3.isInf -> f3.infSign, (magZero && f3.effSub) -> (m === RoundingMode.RDN.code.U))
      )
    raw.sign := front.signs(0)
    raw.sig := mag
    raw.exp := f3.big.exp -& extra.S
    raw.sticky := f3.sticky
    front
  }

  def minExp(fmt: FloatFormat): Int = fmt.emin - fmt.manBits - extra

  /** Swap, align, add, the rounder's cut points, the output. */
  def cuts(fmt: FloatFormat): Int = 3 + FpRound.cuts(fmt, fmt.precision + extra + 1, Some(minExp(fmt))) + 1

  /** One register per cut point (docs/fmax.md). */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
