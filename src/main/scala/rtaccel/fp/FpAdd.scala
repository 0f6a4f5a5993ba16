package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point adder (or subtractor, with `subtract`): `a + b` (`a - b`)
  * rounded once in the mode. Front half: swap by exponent, align the smaller
  * significand with guard/round/sticky bits, add or subtract; back half:
  * [[FpRound]]. Registers: see [[FpPipeline]] (cuts after the add and at the
  * output).
  *
  * @param rm      Some(mode) fixes the mode at elaboration; None adds an `rm` input
  * @param latency cycles from `in` to `out`
  */
class FpAdd(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int = FpAdd.defaultLatency,
    val subtract: Boolean = false) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name(if (subtract) "FpSub" else "FpAdd", fmt, rm, latency)

  private val p = fmt.precision
  /** Guard, round and sticky positions below the aligned LSB. Two would do
    * (FpRaw needs precision+1 bits when sticky; an effective subtraction with
    * d > extra loses at most one leading bit); three keeps a margin.
    */
  private val extra = 3
  private val pipe = new FpPipeline(latency, cuts = 2)
  private val rmIn = FpUnitIO.roundingMode(rm, io.in.bits.rm)

  private val ua = FpUnpack(fmt, io.in.bits.a)
  private val ub0 = FpUnpack(fmt, io.in.bits.b)
  private val ub = WireInit(ub0)
  if (subtract) ub.sign := !ub0.sign // exact; NaN signs do not matter (canonical NaN out)

  private val aBig = ua.exp >= ub.exp
  private val big = Mux(aBig, ua, ub)
  private val small = Mux(aBig, ub, ua)
  private val dist = (big.exp - small.exp).asUInt
  private val (smallAligned, sticky) = FpUnpack.shiftRightSticky(Cat(small.sig, 0.U(extra.W)), dist)
  private val bigExt = Cat(big.sig, 0.U(extra.W))
  private val effSub = ua.sign =/= ub.sign
  // A true difference is big - (smallAligned + d), d in (0,1) when sticky:
  // = (big - smallAligned - 1) + (1 - d), so subtract the sticky bit too.
  private val diff = bigExt.zext - smallAligned.zext - sticky.asUInt.zext
  private val negative = diff < 0.S // only when the exponents are equal (then no sticky)
  private val mag = Mux(effSub, Mux(negative, (-diff).asUInt, diff.asUInt), bigExt +& smallAligned)

  private val front = Wire(new FpRawStage(p + extra + 1, FpUnpack.expWidth(fmt) + 1, rm.isEmpty))
  private val raw = front.raw
  front.rm.foreach(_ := io.in.bits.rm.get)
  raw.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isInf && effSub)
  raw.isInf := ua.isInf || ub.isInf
  // Exact zero: (-0)+(-0) = -0, x+(-x) = +0 except -0 in RDN (IEEE 754 6.3).
  raw.isZero := mag === 0.U && !sticky
  raw.sign := MuxCase(big.sign ^ (effSub && negative), Seq(
    ua.isInf -> ua.sign,
    ub.isInf -> ub.sign,
    (mag === 0.U && effSub) -> (rmIn === RoundingMode.RDN.code.U)
  ))
  raw.sig := mag
  raw.exp := big.exp -& extra.S
  raw.sticky := sticky

  private val mid = pipe.cut(io.in.valid, front)
  private val rounded = FpRound(fmt, mid.bits.raw, FpUnitIO.roundingMode(rm, mid.bits.rm),
    minExp = Some(fmt.emin - fmt.manBits - extra))
  io.out := pipe.cut(mid.valid, rounded)
  pipe.done()
}

object FpAdd {
  /** One register after the add, one at the output. */
  val defaultLatency: Int = 2
}
