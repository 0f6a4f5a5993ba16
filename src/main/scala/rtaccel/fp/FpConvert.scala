package rtaccel.fp

import chisel3._
import chisel3.util._

/** Converts a value of format `from` to format `to`, rounded once in the mode
  * (exact when `to` is at least as wide in both fields). `FpConvert(FP32, f,
  * Some(RDN))` narrows lower box bounds outward, `Some(RUP)` upper ones.
  * NaN becomes `to`'s canonical NaN. Cuts: after decoding and at the output.
  */
class FpConvert(
    val from: FloatFormat,
    val to: FloatFormat,
    val rm: Option[RoundingMode],
    val latency: Int = FpConvert.defaultLatency
) extends Module {
  val io = IO(new FpUnitIO(new FpUnaryIn(from, rm.isEmpty), UInt(to.width.W)))
  override def desiredName: String = s"FpConvert_${from.name}_to_${to.name}_${RoundingMode.tag(rm)}_l$latency"

  private val pipe = new FpPipeline(latency, cuts = 2)
  private val u = FpUnpack(from, io.in.bits.a)
  private val front = Wire(new FpRawStage(from.precision, FpUnpack.expWidth(from), rm.isEmpty))
  front.rm.foreach(_ := io.in.bits.rm.get)
  front.raw.isNaN := u.isNaN
  front.raw.isInf := u.isInf
  front.raw.isZero := u.isZero
  front.raw.sign := u.sign
  front.raw.sig := u.sig
  front.raw.exp := u.exp
  front.raw.sticky := false.B

  private val mid = pipe.cut(io.in.valid, front)
  io.out := pipe.cut(
    mid.valid,
    FpRound(to, mid.bits.raw, FpUnitIO.roundingMode(rm, mid.bits.rm), minExp = Some(from.emin - from.manBits))
  )
  pipe.done()
}

object FpConvert {
  val defaultLatency: Int = 1
}
