package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point adder (or subtractor, with `subtract`): `a + b` (`a - b`)
  * rounded once in the mode. Front: compare the exponents and swap; align
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

  private val p = fmt.precision
  private val extra = FpAdd.extra
  private val pipe = new FpPipeline(latency, FpAdd.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val sw = p + extra
  private val ew = FpUnpack.expWidth(fmt)

  private val ua = FpUnpack(fmt, io.in.bits.a)
  private val ub0 = FpUnpack(fmt, io.in.bits.b)
  private val ub = WireInit(ub0)
  if (subtract) ub.sign := !ub0.sign // exact; NaN signs do not matter (canonical NaN out)

  private val dynamicRm = rm.isEmpty

  /** The front's state between its cuts. */
  class Front extends Bundle {
    val big = new FpUnpacked(fmt)
    val smallSig = UInt(p.W)
    val dist = UInt((fmt.expBits + 1).W)
    val effSub = Bool()
    val isNaN = Bool()
    val isInf = Bool()
    val infSign = Bool()
    val smallAligned = UInt(sw.W)
    val sticky = Bool()
    val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
  }

  // Cut 1: swap by exponent. Both operands' LSB exponents carry the same
  // offset from their (subnormal-adjusted) fields, so fields are compared and
  // subtracted directly, both ways at once: no chain waits on another.
  private val f0 = Wire(new Front)
  f0 := DontCare
  f0.rm.foreach(_ := io.in.bits.rm.get)
  private def field(bits: UInt): UInt = {
    val e = bits(fmt.width - 2, fmt.manBits)
    Mux(e === 0.U, 1.U(fmt.expBits.W), e)
  }
  private val fa = field(io.in.bits.a)
  private val fb = field(io.in.bits.b)
  private val aBig = fa >= fb // = ua.exp >= ub.exp
  private val big = Mux(aBig, ua, ub)
  f0.big := big
  f0.smallSig := Mux(aBig, ub.sig, ua.sig)
  f0.dist := Mux(aBig, fa -& fb, fb -& fa) // = big.exp - small.exp >= 0
  f0.effSub := ua.sign =/= ub.sign
  f0.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isInf && f0.effSub)
  f0.isInf := ua.isInf || ub.isInf
  f0.infSign := Mux(ua.isInf, ua.sign, ub.sign)
  private val f1 = stages(f0)

  // Cut 2: align the smaller significand.
  private val f2 = Wire(new Front)
  f2 := f1
  private val (smallAligned, sticky) = FpUnpack.shiftRightSticky(Cat(f1.smallSig, 0.U(extra.W)), f1.dist)
  f2.smallAligned := smallAligned
  f2.sticky := sticky
  private val f3 = stages(f2)

  // Cut 3: add or subtract. A true difference is big - (smallAligned + d),
  // d in (0,1) when sticky: = (big - smallAligned - 1) + (1 - d), so subtract
  // the sticky bit too. Its negation is formed beside it, not after it.
  private val bigExt = Cat(f3.big.sig, 0.U(extra.W))
  private val diff = bigExt.zext - f3.smallAligned.zext - f3.sticky.asUInt.zext
  private val negDiff = f3.smallAligned.zext + f3.sticky.asUInt.zext - bigExt.zext
  private val negative = diff < 0.S // only when the exponents are equal (then no sticky)
  private val mag = Mux(f3.effSub, Mux(negative, negDiff.asUInt, diff.asUInt), bigExt +& f3.smallAligned)

  private val front = Wire(new FpRawStage(sw + 1, ew + 1, rm.isEmpty))
  private val raw = front.raw
  front.rm.foreach(_ := f3.rm.get)
  raw.isNaN := f3.isNaN
  raw.isInf := f3.isInf
  // Exact zero: (-0)+(-0) = -0, x+(-x) = +0 except -0 in RDN (IEEE 754 6.3).
  raw.isZero := mag === 0.U && !f3.sticky
  raw.sign := MuxCase(
    f3.big.sign ^ (f3.effSub && negative),
    Seq(
      f3.isInf -> f3.infSign,
      (mag === 0.U && f3.effSub) -> (FpUnitIO.roundingMode(rm, f3.rm) === RoundingMode.RDN.code.U)
    )
  )
  raw.sig := mag
  raw.exp := f3.big.exp -& extra.S
  raw.sticky := f3.sticky

  private val mid = stages(front)
  private val rounded =
    FpRound(fmt, mid.raw, FpUnitIO.roundingMode(rm, mid.rm), minExp = Some(FpAdd.minExp(fmt)), stages = Some(stages))
  io.out := pipe.cut(stages.valid, rounded)
  pipe.done()
}

object FpAdd {

  /** Guard, round and sticky positions below the aligned LSB. Two would do
    * (FpRaw needs precision+1 bits when sticky; an effective subtraction with
    * d > extra loses at most one leading bit); three keeps a margin.
    */
  val extra: Int = 3
  def minExp(fmt: FloatFormat): Int = fmt.emin - fmt.manBits - extra

  /** Swap, align, add, the rounder's cut points, the output. */
  def cuts(fmt: FloatFormat): Int = 3 + FpRound.cuts(fmt, fmt.precision + extra + 1, Some(minExp(fmt))) + 1

  /** One register per cut point (docs/fmax.md). */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
