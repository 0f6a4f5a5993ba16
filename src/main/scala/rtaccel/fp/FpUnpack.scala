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

  /** Leading zeros of a nonzero `x` (what `PriorityEncoder(Reverse(x))`
    * gives), in log2Ceil(width) bits, by a binary tree: log depth, where
    * PriorityEncoder is a chain of muxes as long as `x` (docs/fmax.md). For
    * x = 0 the count is meaningless; every caller flags a zero apart.
    */
  def leadingZeros(x: UInt): UInt = {
    val w = x.getWidth
    val k = log2Ceil(w)
    // Padded with ones below the LSB, so a nonzero x counts the same and the width is 2^k.
    val padded = if ((1 << k) > w) Cat(x, Fill((1 << k) - w, 1.U(1.W))) else x
    def tree(v: UInt): (Bool, UInt) =
      if (v.getWidth == 2) (!v.orR, (!v(1)).asUInt)
      else {
        val h = v.getWidth / 2
        val (zHi, cHi) = tree(v(v.getWidth - 1, h))
        val (zLo, cLo) = tree(v(h - 1, 0))
        (zHi && zLo, Mux(zHi, Cat(1.U(1.W), cLo), Cat(0.U(1.W), cHi)))
      }
    require(w >= 2, s"leadingZeros: a ${w}-bit value")
    tree(padded)._2
  }

  /** Trailing zeros of a nonzero `x`, in log2Ceil(width) bits ([[leadingZeros]] of its bits reversed). */
  def trailingZeros(x: UInt): UInt = leadingZeros(Reverse(x))

  /** `(x << amount)` cut to `x`'s width, by one 2:1 mux stage per amount bit, the amount's
    * most significant bit first: [[leadingZeros]] settles its high bits first (its low bits pass
    * through every level of the tree), so a shift by a count just computed waits on the count's
    * last bit for one mux, not for a whole shifter. (Bits shifted past the top never return, so
    * the stages' order does not change the result.)
    */
  def shiftLeftMsbFirst(x: UInt, amount: UInt): UInt = {
    val w = x.getWidth
    (amount.getWidth - 1 to 0 by -1).foldLeft(x) { (v, i) =>
      if ((1 << i) >= w) Mux(amount(i), 0.U(w.W), v) else Mux(amount(i), (v << (1 << i))(w - 1, 0), v)
    }
  }
}
