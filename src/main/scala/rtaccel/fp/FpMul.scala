package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point multiplier: the exact `precision x precision` significand
  * product, rounded once by [[FpRound]] (which also normalises subnormal
  * operands' products). Registers: see [[FpPipeline]] (cuts after the
  * multiply and at the output).
  */
class FpMul(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int = FpMul.defaultLatency) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name("FpMul", fmt, rm, latency)

  private val p = fmt.precision
  private val pipe = new FpPipeline(latency, cuts = 2)
  private val ua = FpUnpack(fmt, io.in.bits.a)
  private val ub = FpUnpack(fmt, io.in.bits.b)

  private val front = Wire(new FpRawStage(2 * p, FpUnpack.expWidth(fmt) + 1, rm.isEmpty))
  private val raw = front.raw
  front.rm.foreach(_ := io.in.bits.rm.get)
  raw.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isZero) || (ub.isInf && ua.isZero)
  raw.isInf := ua.isInf || ub.isInf
  raw.isZero := ua.isZero || ub.isZero
  raw.sign := ua.sign ^ ub.sign
  raw.sig := ua.sig * ub.sig
  raw.exp := ua.exp +& ub.exp
  raw.sticky := false.B

  private val mid = pipe.cut(io.in.valid, front)
  io.out := pipe.cut(mid.valid, FpRound(fmt, mid.bits.raw, FpUnitIO.roundingMode(rm, mid.bits.rm)))
  pipe.done()
}

object FpMul {
  /** One register after the multiply (DSP output), one at the output. */
  val defaultLatency: Int = 2
}
