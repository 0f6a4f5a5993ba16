package rtaccel.fp

import RoundingMode._

/** The model's single rounding step: exact value in, nearest representable
  * neighbour in the mode out. Shared by every [[FpModel]] operation so that
  * each result is rounded exactly once.
  */
object FpRounding {

  /** Rounds `(-1)^sign * (mag + d) * 2^exp` to `fmt`, where `d` is 0 if
    * `!sticky` and some unknown value in (0, 1) if `sticky` (an inexact
    * quotient). With `sticky`, `mag` must have at least `precision + 1` bits so
    * that the unknown part lies strictly below the guard bit.
    */
  def round(fmt: FloatFormat, rm: RoundingMode, sign: Boolean, mag: BigInt, exp: Int, sticky: Boolean): BigInt = {
    require(mag >= 0, s"round: negative magnitude $mag")
    if (mag == 0) {
      require(!sticky, "round: sticky bit set on a zero magnitude")
      return fmt.zero(sign)
    }
    require(
      !sticky || mag.bitLength >= fmt.precision + 1,
      s"round: sticky needs >= ${fmt.precision + 1} bits, got ${mag.bitLength}"
    )
    val msbExp = exp + mag.bitLength - 1
    // Weight of the result's LSB: precision bits below the MSB, but never
    // below the subnormal quantum 2^(emin - manBits).
    val quantum = math.max(msbExp - fmt.manBits, fmt.emin - fmt.manBits)
    val shift = quantum - exp
    var kept =
      if (shift <= 0) mag << -shift // exact: no bits fall below the quantum
      else {
        val k = mag >> shift
        val rem = mag - (k << shift)
        val half = BigInt(1) << (shift - 1)
        val inexact = rem != 0 || sticky
        val up = rm match {
          case RNE => rem > half || (rem == half && (sticky || k.testBit(0)))
          case RTZ => false
          case RDN => sign && inexact
          case RUP => !sign && inexact
        }
        if (up) k + 1 else k
      }
    var q = quantum
    if (kept.bitLength > fmt.precision) { kept >>= 1; q += 1 } // rounding carried into a new binade
    if (kept == 0) fmt.zero(sign)
    else if (kept.bitLength < fmt.precision) fmt.pack(sign, 0, kept) // subnormal (q is the subnormal quantum)
    else {
      val expField = q + fmt.manBits + fmt.bias
      if (expField >= fmt.maxExpField) overflow(fmt, rm, sign)
      else fmt.pack(sign, expField, kept.clearBit(fmt.manBits))
    }
  }

  /** IEEE overflow: infinity if the mode rounds away from zero on this side, else the largest finite. */
  def overflow(fmt: FloatFormat, rm: RoundingMode, sign: Boolean): BigInt = {
    val toInfinity = rm match {
      case RNE => true
      case RTZ => false
      case RDN => sign
      case RUP => !sign
    }
    if (toInfinity) fmt.infinity(sign) else fmt.maxFinite(sign)
  }
}
