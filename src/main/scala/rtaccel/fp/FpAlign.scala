package rtaccel.fp

import chisel3._
import chisel3.util._

/** The adder's alignment shift on DSP48E1s: the smaller significand `x` (p bits) with FpAdd.extra zero bits
  * below it, shifted right by the exponent difference `d`, and the sticky bit of what falls off, as the
  * product `x * 2^(sw - min(d, sw))` (sw = p + extra) on [[DspMul]]. As a barrel shifter with its sticky
  * logic beside it, this was about a fifth of the adder's LUTs (107 of 506 at FP32); here the fabric keeps
  * only the decode of `d` into the one-hot multiplier (sw + 1 bits: two DSP48E1s at FP32, one for p
  * <= 13, whose one-hot and its sign bit fit the B port) and an OR of the product's low bits.
  *
  * Exactness: for d <= sw, `(x << extra) >> d` = floor(x 2^(extra - d)) = floor(P / 2^p) with
  * P = x 2^(sw - d), since sw - p = extra, and the bits it drops are P mod 2^p. For d > sw the shift
  * leaves 0 and drops all of x; the clamped multiplier 2^0 gives P = x < 2^p: again floor(P / 2^p) = 0 and
  * P mod 2^p = x.
  */
object FpAlign {

  /** The multiplier's width: 2^(sw - min(d, sw)) has sw + 1 bits. */
  def width(fmt: FloatFormat): Int = fmt.precision + FpAdd.extra + 1

  /** The multiplier 2^(sw - min(d, sw)), one-hot: bit k set when d = sw - k, bit 0 also when d > sw; `d` is
    * at most `dMax`. The equalities read only the bits of `d` that count to dMax (the adder's difference of
    * 8-bit fields has a ninth bit, always 0: read by every bit of the decode it cost 17 of the FP32 adder's
    * LUTs). The clamp reads all of `d`, which keeps the ninth bit's register and the difference's carry
    * chain as they were (without it the two differences of the swap stage merged into one chain behind the
    * subnormal test, 4.94 ns alone and 5.53 ns in a box lane).
    */
  def oneHot(fmt: FloatFormat, d: UInt, dMax: Int): UInt = {
    val sw = width(fmt) - 1
    val low = d(log2Ceil(dMax + 1).min(d.getWidth) - 1, 0)
    VecInit((0 to sw).map(k => if (k == 0) d >= sw.U else low === (sw - k).U)).asUInt
  }

  /** The aligned significand (sw bits) and its sticky bit, from the product P (at least p + sw bits). */
  def aligned(fmt: FloatFormat, product: UInt): (UInt, Bool) = {
    val p = fmt.precision
    val sw = width(fmt) - 1
    (product(p + sw - 1, p), product(p - 1, 0).orR)
  }
}
