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

  private val pipe = new FpPipeline(latency, FpMul.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpMul.front(fmt, io.in.bits))
  // Rounded first: its cuts advance `stages.valid`.
  private val rounded = FpRound(fmt, mid.raw, FpUnitIO.roundingMode(rm, mid.rm), stages = Some(stages))
  io.out := pipe.cut(stages.valid, rounded)
  pipe.done()
}

/** [[FpMul]] rounded both down (RDN) and up (RUP) from one product: one
  * multiplier and normaliser, two final roundings (FpRound.inModes). Each
  * result is bit for bit the single-mode unit's; same cuts and latency.
  */
class FpMulDnUp(val fmt: FloatFormat, val latency: Int = FpMul.defaultLatency) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, false), new FpDnUp(fmt)))
  override def desiredName: String = s"FpMulDnUp_${fmt.name}_l$latency"

  private val pipe = new FpPipeline(latency, FpMul.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpMul.front(fmt, io.in.bits))
  private val rounded = FpRound.inModes(fmt, mid.raw, FpDnUp.modes(mid.raw.sign), None, Some(stages))
  io.out := pipe.cut(stages.valid, FpDnUp(fmt, rounded))
  pipe.done()
}

object FpMul {

  /** The exact product, unrounded (the rounding mode passed on when it is a runtime input). */
  def front(fmt: FloatFormat, in: FpBinaryIn): FpRawStage = {
    val p = fmt.precision
    val ua = FpUnpack(fmt, in.a)
    val ub = FpUnpack(fmt, in.b)
    val front = Wire(new FpRawStage(2 * p, FpUnpack.expWidth(fmt) + 1, in.rm.isDefined))
    val raw = front.raw
    front.rm.foreach(_ := in.rm.get)
    raw.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isZero) || (ub.isInf && ua.isZero)
    raw.isInf := ua.isInf || ub.isInf
    raw.isZero := ua.isZero || ub.isZero
    raw.sign := ua.sign ^ ub.sign
    raw.sig := ua.sig * ub.sig
    raw.exp := ua.exp +& ub.exp
    raw.sticky := false.B
    front
  }

  /** The multiply, the rounder's cut points, the output. */
  def cuts(fmt: FloatFormat): Int = 1 + FpRound.cuts(fmt, 2 * fmt.precision) + 1

  /** One register per cut point (the same for every format: the product always takes the full rounder). */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
