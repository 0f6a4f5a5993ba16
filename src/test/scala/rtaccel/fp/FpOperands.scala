package rtaccel.fp

import scala.util.Random

/** Operand generators shared by the model spec and the unit specs: a corner
  * list first, then seeded random pairs that mix exponents so that alignment,
  * cancellation, rounding ties, overflow and underflow are all hit often.
  */
object FpOperands {

  /** Corner values of a format: ±0, ±inf, NaNs, subnormal and normal extremes,
    * ulp neighbours of 1, and powers of two that make halfway cases with 1.
    */
  def corners(fmt: FloatFormat): Seq[BigInt] = {
    import fmt._
    val one = fmt.one(false)
    val p = precision
    def pow2(e: Int): BigInt = FpRounding.round(fmt, RoundingMode.RNE, sign = false, BigInt(1), e, sticky = false)
    val positives = Seq(
      zero(false),
      infinity(false),
      minSubnormal(false),
      minSubnormal(false) + 1,
      maxSubnormal(false),
      minNormal(false),
      minNormal(false) + 1,
      maxFinite(false),
      maxFinite(false) - 1,
      one,
      one + 1,
      one - 1,
      one + 2,
      pack(false, bias, BigInt(1) << (manBits - 1)) /* 1.5 */,
      pow2(1),
      pow2(-p),
      pow2(-p - 1),
      pow2(-p + 1),
      pack(false, bias - p, (BigInt(1) << manBits) - 1),
      pow2(emax),
      pow2(emin - manBits + 1),
      pack(false, bias + 1, (BigInt(1) << manBits) - 1)
    ).distinct
    val nans = Seq(canonicalNaN, canonicalNaN.setBit(width - 1), pack(false, maxExpField, 1))
    positives.flatMap(x => Seq(x, negate(x))) ++ nans
  }

  /** All ordered pairs of corners. */
  def cornerPairs(fmt: FloatFormat): Seq[(BigInt, BigInt)] = {
    val c = corners(fmt)
    for (a <- c; b <- c) yield (a, b)
  }

  private def randomFrac(fmt: FloatFormat, rnd: Random): BigInt = rnd.nextInt(4) match {
    case 0 => BigInt(fmt.manBits, rnd)
    case 1 => (BigInt(fmt.manBits, rnd) >> rnd.nextInt(fmt.manBits)) << rnd.nextInt(fmt.manBits) & ((BigInt(
        1
      ) << fmt.manBits) - 1) // few low bits: ties
    case 2 => ((BigInt(1) << fmt.manBits) - 1) ^ BigInt(rnd.nextInt(4)) // near all ones: carries
    case _ => BigInt(rnd.nextInt(4)) // near zero fraction
  }

  private def withExp(fmt: FloatFormat, rnd: Random, expField: Int): BigInt =
    fmt.pack(rnd.nextBoolean(), expField.max(0).min(fmt.maxExpField - 1), randomFrac(fmt, rnd))

  /** A random finite or special value, exponent uniform over the whole range. */
  def single(fmt: FloatFormat, rnd: Random): BigInt = rnd.nextInt(20) match {
    case 0 => val c = corners(fmt); c(rnd.nextInt(c.size))
    case 1 => fmt.pack(rnd.nextBoolean(), 0, BigInt(fmt.manBits, rnd)) // subnormal
    case 2 => BigInt(fmt.width, rnd) // any bit pattern
    case _ => withExp(fmt, rnd, rnd.nextInt(fmt.maxExpField))
  }

  /** A random operand pair, with `b` placed relative to `a` in one of several ways. */
  def pair(fmt: FloatFormat, rnd: Random): (BigInt, BigInt) = {
    val a = single(fmt, rnd)
    val ea = fmt.expField(a)
    val p = fmt.precision
    val b = rnd.nextInt(9) match {
      case 0 => single(fmt, rnd) // independent: mostly far exponents
      case 1 => withExp(fmt, rnd, ea) // same exponent
      case 2 => withExp(fmt, rnd, ea + rnd.nextInt(2 * p + 7) - p - 3) // near exponents
      case 3 => // cancellation: -(a +- a few ulps)
        val n = fmt.negate(a) + rnd.nextInt(5) - 2
        if (n >= 0 && n < (BigInt(1) << fmt.width)) n else a
      case 4 => fmt.pack(rnd.nextBoolean(), 0, BigInt(fmt.manBits, rnd) >> rnd.nextInt(fmt.manBits)) // subnormal
      case 5 => withExp(fmt, rnd, 2 * fmt.bias - ea + rnd.nextInt(7) - 3) // product near 1
      case 6 => withExp(fmt, rnd, fmt.bias + fmt.emax - ea + rnd.nextInt(5) - 2) // product near overflow
      case 7 =>
        withExp(
          fmt,
          rnd,
          fmt.bias + fmt.emin - fmt.manBits - ea + fmt.bias + rnd.nextInt(fmt.manBits + 4) - 2
        ) // product near underflow
      case _ => // quotient a/b near overflow or near underflow (b placed for a/b; the pair may be swapped below)
        // The quotient's biased exponent is about ea - eb + bias.
        if (rnd.nextBoolean()) withExp(fmt, rnd, ea + fmt.bias - (fmt.maxExpField - 1) + rnd.nextInt(6) - 2)
        else withExp(fmt, rnd, ea + fmt.bias - 1 + rnd.nextInt(fmt.manBits + 5) - 2)
    }
    if (rnd.nextBoolean()) (a, b) else (b, a)
  }
}
