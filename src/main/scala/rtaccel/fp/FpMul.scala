package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point multiplier: the exact `precision x precision` significand
  * product, rounded once by [[FpRound]] (which also normalises subnormal
  * operands' products). Cut points ([[FpPipeline]]): after the unpacked
  * operands (the DSP48s' input registers), the product's ([[DspMul]]: one per
  * DSP48 and one after the last sum), the rounder's, the output; the default
  * latency puts one register on each.
  */
class FpMul(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int = FpMul.defaultLatency)
    extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name("FpMul", fmt, rm, latency)

  private val pipe = new FpPipeline(latency, FpMul.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = FpMul.front(fmt, io.in.bits, stages)
  // Rounded first: its cuts advance `stages.valid`.
  private val rounded =
    FpRound(
      fmt,
      mid.meta.raw,
      FpUnitIO.roundingMode(rm, mid.meta.rm),
      stages = Some(stages),
      trailingZeros = Some(mid.tz)
    )
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
  private val mid = FpMul.front(fmt, io.in.bits, stages)
  private val rounded =
    FpRound.inModes(fmt, mid.meta.raw, FpDnUp.modes(mid.meta.raw.sign), None, Some(stages), Some(mid.tz))
  io.out := pipe.cut(stages.valid, FpDnUp(fmt, rounded))
  pipe.done()
}

/** What the multiplier carries through the product's cuts: the unrounded result but its significand, the
  * operands' significands and the product's partials. */
class FpMulState(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  private val p = fmt.precision
  val meta = new FpRawStage(2 * p, FpUnpack.expWidth(fmt) + 1, dynamicRm)

  /** The product's trailing zeros, the sum of the operands' (a product of odd numbers is odd), counted
    * beside the DSP48s for the rounder's tail bit ([[FpRound.inModes]]); meaningless for a zero operand.
    * Each operand's count is registered with the operands and added in the first product stage (the count
    * and the add in one cycle were 5.29-5.95 ns).
    */
  val tzA = UInt(log2Ceil(p).W)
  val tzB = UInt(log2Ceil(p).W)
  val tz = UInt(FpMul.tzWidth(fmt).W)
  val a = UInt(p.W)
  val b = UInt(p.W)
  val dsp = new DspPartials(p + 1, p + 1)
}

/** The exact product (`meta`) and its trailing zeros (`tz`, [[FpMulState]]). */
class FpMulMid(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  val meta = new FpRawStage(2 * fmt.precision, FpUnpack.expWidth(fmt) + 1, dynamicRm)
  val tz = UInt(FpMul.tzWidth(fmt).W)
}

object FpMul {

  /** The exact product, unrounded (the rounding mode passed on when it is a runtime input), after the cut of
    * the unpacked operands and the product's cuts. */
  def front(fmt: FloatFormat, in: FpBinaryIn, stages: FpStages): FpMulMid = {
    val p = fmt.precision
    val ua = FpUnpack(fmt, in.a)
    val ub = FpUnpack(fmt, in.b)
    val s0 = Wire(new FpMulState(fmt, in.rm.isDefined))
    s0 := DontCare
    val raw = s0.meta.raw
    s0.meta.rm.foreach(_ := in.rm.get)
    raw.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isZero) || (ub.isInf && ua.isZero)
    raw.isInf := ua.isInf || ub.isInf
    raw.isZero := ua.isZero || ub.isZero
    raw.sign := ua.sign ^ ub.sign
    raw.exp := ua.exp +& ub.exp
    raw.sticky := false.B
    s0.a := ua.sig
    s0.b := ub.sig
    s0.tzA := FpUnpack.trailingZeros(ua.sig)
    s0.tzB := FpUnpack.trailingZeros(ub.sig)
    // The operands in registers, then one stage per product cut.
    val last = (1 to DspMul.cuts(p + 1)).foldLeft(stages(s0)) { (prev, s) =>
      val n = Wire(new FpMulState(fmt, in.rm.isDefined))
      n := prev
      n.dsp := DspMul.step(s, prev.a.zext, prev.b.zext, prev.dsp)
      if (s == 1) n.tz := prev.tzA +& prev.tzB
      stages(n)
    }
    val out = Wire(new FpMulMid(fmt, in.rm.isDefined))
    out.meta := last.meta
    out.meta.raw.sig := DspMul.result(last.a.zext, last.b.zext, last.dsp).asUInt(2 * p - 1, 0)
    out.tz := last.tz
    out
  }

  /** Holds every sum of two operands' trailing-zero counts (each below p). */
  def tzWidth(fmt: FloatFormat): Int = log2Ceil(fmt.precision) + 1

  /** The unpacked operands, the product ([[DspMul]]), the rounder's cut points, the output. */
  def cuts(fmt: FloatFormat): Int =
    1 + DspMul.cuts(fmt.precision + 1) + FpRound.cuts(fmt, 2 * fmt.precision) + 1

  /** One register per cut point at FP32, whose product takes two DSP48s; a narrower format's single DSP48
    * takes a cut less, and its spare register sits at the output. */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
