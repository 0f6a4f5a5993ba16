package rtaccel.fp

/** Exact rationals for checking the model against mathematics, not against
  * itself: `num / den` with `den > 0`.
  */
final case class Rational(num: BigInt, den: BigInt) extends Ordered[Rational] {
  require(den > 0, s"Rational: denominator must be positive, got $den")
  def +(o: Rational): Rational = Rational(num * o.den + o.num * den, den * o.den)
  def -(o: Rational): Rational = Rational(num * o.den - o.num * den, den * o.den)
  def *(o: Rational): Rational = Rational(num * o.num, den * o.den)
  def /(o: Rational): Rational = {
    require(o.num != 0, "Rational: division by zero")
    if (o.num > 0) Rational(num * o.den, den * o.num) else Rational(-num * o.den, -den * o.num)
  }
  def abs: Rational = Rational(num.abs, den)
  def compare(o: Rational): Int = (num * o.den).compare(o.num * den)
}

object FpExact {

  /** The exact value of a finite encoding. */
  def value(fmt: FloatFormat, bits: BigInt): Rational = {
    require(fmt.isFinite(bits), s"${fmt.name}: 0x${bits.toString(16)} is not finite")
    val m = if (fmt.sign(bits)) -fmt.significand(bits) else fmt.significand(bits)
    val e = fmt.lsbExponent(bits)
    if (e >= 0) Rational(m << e, 1) else Rational(m, BigInt(1) << -e)
  }

  /** The next encoding up in value order (-0 steps to +min subnormal; max finite to +inf). */
  def nextUp(fmt: FloatFormat, bits: BigInt): BigInt =
    if (fmt.isZero(bits)) fmt.minSubnormal(false)
    else if (fmt.sign(bits)) bits - 1
    else bits + 1

  /** Extended-real order of a non-NaN encoding against a finite value. */
  private def le(fmt: FloatFormat, bits: BigInt, x: Rational): Boolean =
    if (fmt.isInfinite(bits)) fmt.sign(bits) else value(fmt, bits) <= x
  private def ge(fmt: FloatFormat, bits: BigInt, x: Rational): Boolean =
    if (fmt.isInfinite(bits)) !fmt.sign(bits) else value(fmt, bits) >= x

  /** Checks the four rounded results of one exact value against the IEEE
    * definitions; returns a description of the first violation, if any.
    *  - RDN <= exact <= RUP, and they are equal or adjacent encodings;
    *  - RTZ is whichever of RDN/RUP is toward zero;
    *  - RNE is the nearer of RDN/RUP, ties to the even significand, and
    *    overflows to infinity exactly from 2^emax * (2 - 2^-precision) up.
    */
  def checkRoundings(fmt: FloatFormat, exact: Rational, r: RoundingMode => BigInt): Option[String] = {
    import RoundingMode._
    val (dn, up, tz, ne) = (r(RDN), r(RUP), r(RTZ), r(RNE))
    def hex(x: BigInt) = "0x" + x.toString(16)
    def same(x: BigInt, y: BigInt) = // equal values (±0 equal)
      x == y || (fmt.isZero(x) && fmt.isZero(y))
    if (Seq(dn, up, tz, ne).exists(fmt.isNaN)) return Some("NaN result for a finite exact value")
    if (!le(fmt, dn, exact)) return Some(s"RDN ${hex(dn)} above exact")
    if (!ge(fmt, up, exact)) return Some(s"RUP ${hex(up)} below exact")
    val exactRep = fmt.isFinite(dn) && value(fmt, dn).compare(exact) == 0
    if (exactRep) {
      if (!Seq(up, tz, ne).forall(same(_, dn)))
        return Some(s"exact value ${hex(dn)} but other modes differ: up ${hex(up)} tz ${hex(tz)} ne ${hex(ne)}")
      return None
    }
    // Adjacent encodings (nextUp also steps -inf -> -max and +max -> +inf).
    if (!same(nextUp(fmt, dn), up)) return Some(s"RDN ${hex(dn)} and RUP ${hex(up)} are not adjacent")
    val towardZero = if (exact.num > 0) dn else up
    if (!same(tz, towardZero)) return Some(s"RTZ ${hex(tz)} is not ${hex(towardZero)}")
    val expectNe =
      if (fmt.isInfinite(up) || fmt.isInfinite(dn)) { // beyond the largest finite
        val big = FpExact.value(fmt, fmt.maxFinite(false))
        val threshold = big + halfUlpOfMax(fmt)
        if (exact.abs >= threshold) (if (exact.num > 0) up else dn) else (if (exact.num > 0) dn else up)
      } else {
        val dDn = exact - value(fmt, dn)
        val dUp = value(fmt, up) - exact
        val c = dDn.compare(dUp)
        if (c < 0) dn else if (c > 0) up else if (!fmt.significand(dn).testBit(0)) dn else up
      }
    if (!same(ne, expectNe)) return Some(s"RNE ${hex(ne)} is not ${hex(expectNe)}")
    None
  }

  private def halfUlpOfMax(fmt: FloatFormat): Rational = {
    val e = fmt.emax - fmt.manBits - 1
    if (e >= 0) Rational(BigInt(1) << e, 1) else Rational(1, BigInt(1) << -e)
  }
}
