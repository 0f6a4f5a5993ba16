package rtaccel.fp

import chisel3._
import chisel3.util._

/** A decoded operand: class flags, and for finite values the exact value
  * `(-1)^sign * sig * 2^exp` with `sig` the significand including the hidden
  * bit (not normalised for subnormals; the rounder normalises).
  */
class FpUnpacked(val fmt: FloatFormat) extends Bundle {
  val sign = Bool()
  val isNaN = Bool()
  val isInf = Bool()
  val isZero = Bool()
  val sig = UInt(fmt.precision.W)
  /** Exponent of `sig`'s LSB (unbiased). */
  val exp = SInt(FpUnpack.expWidth(fmt).W)
}

object FpUnpack {
  /** Signed width that holds every LSB exponent of `fmt`, from `emin - manBits` to `emax`. */
  def expWidth(fmt: FloatFormat): Int = log2Ceil(fmt.bias + fmt.manBits + 1) + 2

  def apply(fmt: FloatFormat, bits: UInt): FpUnpacked = {
    require(bits.getWidth == fmt.width, s"FpUnpack: ${bits.getWidth}-bit input for ${fmt.name}")
    val u = Wire(new FpUnpacked(fmt))
    val expField = bits(fmt.width - 2, fmt.manBits)
    val frac = bits(fmt.manBits - 1, 0)
    val expZero = expField === 0.U
    val expOnes = expField.andR
    u.sign := bits(fmt.width - 1)
    u.isNaN := expOnes && frac.orR
    u.isInf := expOnes && !frac.orR
    u.isZero := expZero && !frac.orR
    u.sig := Cat(!expZero, frac)
    // Subnormals share the LSB weight of exponent field 1.
    val w = expWidth(fmt)
    u.exp := Mux(expZero, 1.U, expField).zext.pad(w) - (fmt.bias + fmt.manBits).S(w.W)
    u
  }

  /** Shifts `x` right by `amount` (clamped to its width); returns the shifted
    * value and whether any 1 bit fell off the end (the sticky bit).
    */
  def shiftRightSticky(x: UInt, amount: UInt): (UInt, Bool) = {
    val w = x.getWidth
    val amt = Mux(amount > w.U, w.U, amount)(log2Ceil(w + 1) - 1, 0)
    val ext = Cat(x, 0.U(w.W)) >> amt
    (ext(2 * w - 1, w), ext(w - 1, 0).orR)
  }
}
