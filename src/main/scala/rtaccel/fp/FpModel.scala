package rtaccel.fp

import RoundingMode._

/** The bit-exact golden model of every floating-point unit, and the reference
  * the datapath golden models are built on.
  *
  * Each operation decodes its operands to exact integers `(-1)^s * mag * 2^exp`,
  * computes the exact result with BigInt arithmetic (a quotient keeps a sticky
  * remainder bit), then rounds ONCE to the format in the given mode
  * ([[FpRounding.round]]). Operands and results are raw bit patterns of `fmt`
  * (`BigInt`, in `[0, 2^width)`). Special values follow IEEE-754, with the
  * subnormal and NaN policy stated in [[FloatFormat]]: NaN results are always
  * the format's canonical NaN.
  *
  * min/max are IEEE 754-2019 minimumNumber/maximumNumber: a NaN operand loses
  * (the other operand is returned; NaN only if both are NaN) and -0 < +0. The
  * box test relies on "NaN loses": a NaN slab distance must not shrink the
  * [tmin, tmax] interval. For non-NaN operands this equals JVM `Math.min/max`.
  */
object FpModel {

  /** a + b, rounded in `rm`. */
  def add(fmt: FloatFormat, rm: RoundingMode, a: BigInt, b: BigInt): BigInt = {
    fmt.checkBits(a); fmt.checkBits(b)
    val (sa, sb) = (fmt.sign(a), fmt.sign(b))
    if (fmt.isNaN(a) || fmt.isNaN(b)) fmt.canonicalNaN
    else if (fmt.isInfinite(a) && fmt.isInfinite(b)) { if (sa == sb) a else fmt.canonicalNaN }
    else if (fmt.isInfinite(a)) a
    else if (fmt.isInfinite(b)) b
    else {
      val (ea, eb) = (fmt.lsbExponent(a), fmt.lsbExponent(b))
      val e = math.min(ea, eb)
      val ma = fmt.significand(a) << (ea - e)
      val mb = fmt.significand(b) << (eb - e)
      val sum = (if (sa) -ma else ma) + (if (sb) -mb else mb)
      // An exact zero sum is -0 only for (-0)+(-0), or for x+(-x) in RDN (IEEE 754 6.3).
      val zeroSign = if (sa == sb) sa else rm == RDN
      if (sum == 0) fmt.zero(zeroSign)
      else FpRounding.round(fmt, rm, sum < 0, sum.abs, e, sticky = false)
    }
  }

  /** a - b, rounded in `rm` (a + (-b); the sign flip is exact). */
  def sub(fmt: FloatFormat, rm: RoundingMode, a: BigInt, b: BigInt): BigInt =
    add(fmt, rm, a, fmt.negate(fmt.checkBits(b)))

  /** a * b, rounded in `rm`. */
  def mul(fmt: FloatFormat, rm: RoundingMode, a: BigInt, b: BigInt): BigInt = {
    fmt.checkBits(a); fmt.checkBits(b)
    val sign = fmt.sign(a) ^ fmt.sign(b)
    if (fmt.isNaN(a) || fmt.isNaN(b)) fmt.canonicalNaN
    else if (fmt.isInfinite(a) || fmt.isInfinite(b)) {
      if (fmt.isZero(a) || fmt.isZero(b)) fmt.canonicalNaN else fmt.infinity(sign)
    } else if (fmt.isZero(a) || fmt.isZero(b)) fmt.zero(sign)
    else
      FpRounding.round(
        fmt,
        rm,
        sign,
        fmt.significand(a) * fmt.significand(b),
        fmt.lsbExponent(a) + fmt.lsbExponent(b),
        sticky = false
      )
  }

  /** a / b, correctly rounded in `rm`. */
  def div(fmt: FloatFormat, rm: RoundingMode, a: BigInt, b: BigInt): BigInt = {
    fmt.checkBits(a); fmt.checkBits(b)
    val sign = fmt.sign(a) ^ fmt.sign(b)
    if (fmt.isNaN(a) || fmt.isNaN(b)) fmt.canonicalNaN
    else if (fmt.isInfinite(a)) { if (fmt.isInfinite(b)) fmt.canonicalNaN else fmt.infinity(sign) }
    else if (fmt.isInfinite(b)) fmt.zero(sign)
    else if (fmt.isZero(b)) { if (fmt.isZero(a)) fmt.canonicalNaN else fmt.infinity(sign) }
    else if (fmt.isZero(a)) fmt.zero(sign)
    else {
      val (ma, mb) = (fmt.significand(a), fmt.significand(b))
      // Scale the dividend so the quotient has >= precision+3 bits; the
      // remainder then only needs to say "nonzero" (the sticky bit).
      val k = math.max(0, fmt.precision + 3 + mb.bitLength - ma.bitLength)
      val (q, r) = (ma << k) /% mb
      FpRounding.round(fmt, rm, sign, q, fmt.lsbExponent(a) - fmt.lsbExponent(b) - k, sticky = r != 0)
    }
  }

  /** 1 / a, correctly rounded in `rm`. */
  def recip(fmt: FloatFormat, rm: RoundingMode, a: BigInt): BigInt = div(fmt, rm, fmt.one(false), a)

  /** Converts a value of format `from` to format `to`, rounding in `rm` (exact when widening). */
  def convert(from: FloatFormat, to: FloatFormat, rm: RoundingMode, a: BigInt): BigInt = {
    from.checkBits(a)
    val sign = from.sign(a)
    if (from.isNaN(a)) to.canonicalNaN
    else if (from.isInfinite(a)) to.infinity(sign)
    else if (from.isZero(a)) to.zero(sign)
    else FpRounding.round(to, rm, sign, from.significand(a), from.lsbExponent(a), sticky = false)
  }
  def fromFloat32(fmt: FloatFormat, rm: RoundingMode, bits: BigInt): BigInt = convert(FloatFormat.FP32, fmt, rm, bits)
  def toFloat32(fmt: FloatFormat, rm: RoundingMode, bits: BigInt): BigInt = convert(fmt, FloatFormat.FP32, rm, bits)

  // ---- comparisons (no rounding) ----

  /** Total order key of a non-NaN value: ±0 both map to 0. */
  private def key(fmt: FloatFormat, a: BigInt): BigInt = if (fmt.sign(a)) -fmt.abs(a) else a
  def unordered(fmt: FloatFormat, a: BigInt, b: BigInt): Boolean =
    fmt.isNaN(fmt.checkBits(a)) || fmt.isNaN(fmt.checkBits(b))

  /** IEEE `a < b`: false if either is NaN; -0 < +0 is false. */
  def lt(fmt: FloatFormat, a: BigInt, b: BigInt): Boolean = !unordered(fmt, a, b) && key(fmt, a) < key(fmt, b)

  /** IEEE `a == b`: false if either is NaN; -0 == +0. */
  def equal(fmt: FloatFormat, a: BigInt, b: BigInt): Boolean = !unordered(fmt, a, b) && key(fmt, a) == key(fmt, b)
  def le(fmt: FloatFormat, a: BigInt, b: BigInt): Boolean = lt(fmt, a, b) || equal(fmt, a, b)

  /** minimumNumber: NaN loses; min(-0, +0) = -0. */
  def min(fmt: FloatFormat, a: BigInt, b: BigInt): BigInt = pick(fmt, a, b, takeMin = true)

  /** maximumNumber: NaN loses; max(-0, +0) = +0. */
  def max(fmt: FloatFormat, a: BigInt, b: BigInt): BigInt = pick(fmt, a, b, takeMin = false)
  private def pick(fmt: FloatFormat, a: BigInt, b: BigInt, takeMin: Boolean): BigInt = {
    val (na, nb) = (fmt.isNaN(fmt.checkBits(a)), fmt.isNaN(fmt.checkBits(b)))
    if (na && nb) fmt.canonicalNaN
    else if (na) b
    else if (nb) a
    else {
      // Signed-magnitude order with -0 below +0: the key of a negative is -(abs)-1.
      def k(x: BigInt) = if (fmt.sign(x)) -fmt.abs(x) - 1 else x
      if ((k(a) <= k(b)) == takeMin) a else b
    }
  }

  // ---- FP32 <-> JVM Float helpers ----

  /** Bits of a JVM Float, every NaN mapped to the canonical one (`floatToIntBits` semantics). */
  def f32Bits(f: Float): BigInt = BigInt(java.lang.Float.floatToIntBits(f)) & 0xffffffffL

  /** Raw bits of a JVM Float (NaN payload kept); for building operands. */
  def f32RawBits(f: Float): BigInt = BigInt(java.lang.Float.floatToRawIntBits(f)) & 0xffffffffL
  def f32(bits: BigInt): Float = java.lang.Float.intBitsToFloat(FloatFormat.FP32.checkBits(bits).toInt)
}
