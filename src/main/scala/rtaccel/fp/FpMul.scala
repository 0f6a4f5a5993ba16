package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point multiplier: the exact `precision x precision` significand
  * product, rounded once by [[FpRound]] (which also normalises subnormal
  * operands' products). Cut points ([[FpPipeline]]): after the multiply (the
  * DSP48 output register), the rounder's, the output; the default latency
  * puts one register on each.
  */
class FpMul(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int = FpMul.defaultLatency)
    extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name("FpMul", fmt, rm, latency)

  private val p = fmt.precision
  private val pipe = new FpPipeline(latency, FpMul.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
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

  private val mid = stages(front)
  // Rounded first: its cuts advance `stages.valid`.
  private val rounded = FpRound(fmt, mid.raw, FpUnitIO.roundingMode(rm, mid.rm), stages = Some(stages))
  io.out := pipe.cut(stages.valid, rounded)
  pipe.done()
}

object FpMul {

  /** The multiply, the rounder's cut points, the output. */
  def cuts(fmt: FloatFormat): Int = 1 + FpRound.cuts(fmt, 2 * fmt.precision) + 1

  /** One register per cut point (the same for every format: the product always takes the full rounder). */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
