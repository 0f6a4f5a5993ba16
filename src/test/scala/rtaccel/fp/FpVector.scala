package rtaccel.fp

import scala.util.Random

/** One stimulus of [[FpUnitsHarness]]: operands `a`, `b` of the format, `f32`
  * for the FP32 -> format conversion, the rounding mode, and whether the beat
  * is valid (bubbles check that `valid` travels with the data).
  */
case class FpVector(a: BigInt, b: BigInt, f32: BigInt, rm: RoundingMode, valid: Boolean)

object FpVector {
  private val F32 = FloatFormat.FP32

  /** Every corner pair in every mode (the FP32 operand cycles through FP32 corners). */
  def corners(fmt: FloatFormat, modes: Seq[RoundingMode]): Seq[FpVector] = {
    val pairs = FpOperands.cornerPairs(fmt)
    val c32 = FpOperands.corners(F32)
    for (rm <- modes; ((a, b), i) <- pairs.zipWithIndex) yield FpVector(a, b, c32(i % c32.size), rm, valid = true)
  }

  /** `n` seeded random vectors in mode `rm`, about one in 16 a bubble. */
  def random(fmt: FloatFormat, rm: RoundingMode, n: Int, rnd: Random): Seq[FpVector] =
    Seq.fill(n) {
      val (a, b) = FpOperands.pair(fmt, rnd)
      // Mostly FP32 values near the format's range, so narrowing rounds and over/underflows.
      val f32 = if (rnd.nextInt(3) == 0) FpOperands.single(F32, rnd)
      else FpModel.toFloat32(fmt, RoundingMode.RNE, FpOperands.single(fmt, rnd)) ^ BigInt(rnd.nextInt(1 << 16))
      FpVector(a, b, f32, rm, valid = rnd.nextInt(16) != 0)
    }
}
