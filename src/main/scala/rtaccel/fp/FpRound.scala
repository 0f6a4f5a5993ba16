package rtaccel.fp

import chisel3._
import chisel3.util._

/** The hardware rounder shared by every arithmetic unit: normalise (leading
  * zero count and shift, clamped at the subnormal boundary), round once in the
  * mode, encode, and substitute special values. It computes exactly what
  * [[FpRounding.round]] computes in the model.
  *
  * `minExp`, when the caller knows it, is the smallest `raw.exp` that can
  * occur. A value on the subnormal grid sits `2 - exp - w - bias` places to
  * the right of "MSB at the top" (independent of the leading-zero count), so
  * if that is never positive one left shift, stopped at the grid, normalises
  * every result and the right shifter is left out (the adder and same-range
  * conversions). Otherwise the rounder normalises fully, keeps p+2 bits plus
  * a sticky bit, and shifts those right onto the grid.
  */
object FpRound {
  def apply(fmt: FloatFormat, raw: FpRaw, rm: UInt, minExp: Option[Int] = None): UInt = {
    val p = fmt.precision
    // At least a guard bit and one more below the kept bits.
    val pad = (p + 2 - raw.sigWidth).max(0)
    val w = raw.sigWidth + pad
    val ew = raw.expWidth.max(FpUnpack.expWidth(fmt)) + log2Ceil(w + 1) + 2
    val sig = if (pad > 0) Cat(raw.sig, 0.U(pad.W)) else raw.sig
    val exp = raw.exp.pad(ew) - pad.S(ew.W)

    val lz = PriorityEncoder(Reverse(sig))
    // Biased exponent of the leading one.
    val biasedExp = exp + (w - 1 + fmt.bias).S(ew.W) - lz.zext.pad(ew)
    val tiny = biasedExp < 1.S
    // Extra right shift that brings a tiny value onto the subnormal grid.
    val subShift = Mux(tiny, (1.S(ew.W) - biasedExp).asUInt, 0.U)
    val maxRightShift = minExp.map(e => 2 - (e - pad) - w - fmt.bias)
    def below(n: UInt): Bool = if (w > p + 2) n(w - p - 3, 0).orR else false.B
    // `window`: the kept p bits, the guard bit and the round bit; `tail`: any 1 below them.
    val (window, tail) =
      if (maxRightShift.exists(_ <= 0)) {
        // Never below the subnormal grid: one left shift, stopped at the grid, does both.
        val n = (sig << (lz - subShift(lz.getWidth - 1, 0)))(w - 1, 0)
        (n(w - 1, w - p - 2), below(n))
      } else {
        // Normalise, keep p+2 bits and a sticky, then shift right onto the subnormal grid
        // (a (p+2)-bit shifter instead of a 2w-bit one).
        val n = (sig << lz)(w - 1, 0)
        val (r, lost) = FpUnpack.shiftRightSticky(n(w - 1, w - p - 2), subShift)
        (r, below(n) || lost)
      }

    val kept = window(p + 1, 2)
    val guard = window(1)
    val rest = window(0) || tail || raw.sticky
    val inexact = guard || rest
    val sign = raw.sign
    val up = MuxLookup(rm, false.B)(Seq(
      RoundingMode.RNE.code.U -> (guard && (rest || kept(0))),
      RoundingMode.RTZ.code.U -> false.B,
      RoundingMode.RDN.code.U -> (sign && inexact),
      RoundingMode.RUP.code.U -> (!sign && inexact)
    ))
    val rounded = kept +& up
    val carry = rounded(p) // 1.11..1 rounded up to 10.00..0: next binade
    val expNormal = Mux(tiny, 1.S(ew.W), biasedExp)
    val expOut = Mux(carry, expNormal + 1.S, Mux(rounded(p - 1), expNormal, 0.S))
    val fracOut = Mux(carry, 0.U, rounded(p - 2, 0))
    val overflow = expOut >= fmt.maxExpField.S

    // Overflow goes to infinity only when the mode rounds away from zero on this side.
    val overflowToInf = rm === RoundingMode.RNE.code.U ||
      (rm === RoundingMode.RUP.code.U && !sign) || (rm === RoundingMode.RDN.code.U && sign)
    val signBit = Cat(sign, 0.U((fmt.width - 1).W))
    MuxCase(Cat(sign, expOut(fmt.expBits - 1, 0), fracOut), Seq(
      raw.isNaN -> fmt.canonicalNaN.U(fmt.width.W),
      raw.isInf -> (signBit | fmt.infinity(false).U),
      (raw.isZero || sig === 0.U) -> signBit,
      overflow -> (signBit | Mux(overflowToInf, fmt.infinity(false).U, fmt.maxFinite(false).U))
    ))
  }
}
