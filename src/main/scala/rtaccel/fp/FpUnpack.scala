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

  /** Shifts `x` right by `amount` (any width); returns the shifted value and
    * whether any 1 bit fell off the end (the sticky bit). The sticky bit is
    * formed beside the shifter from `x` and the amount ([[anyBelow]]), not as
    * an OR of its output (the FP adder's longest path that way, docs/fmax.md).
    * The shifter reads only the amount's low log2Ceil(width + 1) bits (where
    * an amount of `width` or more already shifts everything out), and an OR of
    * the high bits clears its output: with the amount clamped first (a compare
    * and a select in front of the shifter) this was the adder's longest path,
    * 8 cells (4 LUT, 4 MUXF), 5.24 ns.
    */
  def shiftRightSticky(x: UInt, amount: UInt): (UInt, Bool) = {
    val w = x.getWidth
    val lowBits = log2Ceil(w + 1)
    val sticky = anyBelow(x, amount)
    if (amount.getWidth <= lowBits) ((x >> amount)(w - 1, 0), sticky)
    else {
      val out = amount(amount.getWidth - 1, lowBits).orR
      (Mux(out, 0.U(w.W), (x >> amount(lowBits - 1, 0))(w - 1, 0)), sticky)
    }
  }

  /** Whether `x` has a 1 below bit `amount` (the bits a right shift by `amount` drops), in blocks of four
    * bits: the blocks wholly below the amount's block (each block's OR, selected by a compare of the block
    * index with the amount's high bits), and the bits of the amount's own block below its two low bits (a
    * select by the high bits). As `x` masked by [[belowMask]] and ORed, ABC mapped it to three LUT/MUXF7/
    * MUXF8 levels: the adder's longest path, 9 cells (3 LUT, 6 MUXF), 5.00 ns.
    */
  def anyBelow(x: UInt, amount: UInt): Bool = {
    val w = x.getWidth
    val lowBits = log2Ceil(w + 1)
    val a = amount.pad(lowBits)(lowBits - 1, 0)
    val inRange =
      if (lowBits <= 2) (x & belowMask(w, a)).orR
      else {
        val hi = a(lowBits - 1, 2)
        val lo = a(1, 0)
        val blocks = 1 << (lowBits - 2)
        val xs = x.pad(4 * blocks)
        val whole = (0 until blocks).map(b => xs(4 * b + 3, 4 * b).orR && hi > b.U).reduce(_ || _)
        val part = VecInit((0 until blocks).map(b => (0 until 3).map(i => xs(4 * b + i) && lo > i.U).reduce(_ || _)))
        whole || part(hi)
      }
    // An amount of 2^lowBits or more (> w) drops every bit.
    if (amount.getWidth > lowBits) Mux(amount(amount.getWidth - 1, lowBits).orR, x.orR, inRange) else inRange
  }

  /** `w` bits, bit j set when j < amount: the positions a right shift by
    * `amount` drops. A decode of the amount (each bit a function of its low
    * bits and one OR of the rest), not a compare per bit.
    */
  def belowMask(w: Int, amount: UInt): UInt = {
    val lowBits = log2Ceil(w + 1)
    val narrow = amount.getWidth <= lowBits
    val low = if (narrow) amount else amount(lowBits - 1, 0)
    // Bit j < w of the ones shifted left by `low` is set exactly when j >= low (2^lowBits > w ones).
    val below = (~(Fill(1 << lowBits, 1.U(1.W)) << low))(w - 1, 0)
    if (narrow) below else Mux(amount(amount.getWidth - 1, lowBits).orR, Fill(w, 1.U(1.W)), below)
  }

  /** [[shiftRightSticky]] by an amount the caller has already clamped to `x`'s width (a register
    * of log2Ceil(width + 1) bits), so no compare sits in front of the shifter. The sticky bit is
    * formed beside the shifter as there ([[belowMask]]): as an OR of the shifter's dropped bits it
    * was the rounder's longest path in the reciprocal (docs/fmax.md).
    */
  def shiftRightStickyClamped(x: UInt, amt: UInt): (UInt, Bool) = {
    val w = x.getWidth
    require(amt.getWidth <= log2Ceil(w + 1), s"shiftRightStickyClamped: a ${amt.getWidth}-bit amount for $w bits")
    ((x >> amt)(w - 1, 0), (x & belowMask(w, amt)).orR)
  }
}
