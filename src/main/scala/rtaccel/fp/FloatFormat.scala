package rtaccel.fp

/** A binary floating-point format with `expBits` exponent bits and `manBits`
  * stored mantissa (fraction) bits, laid out IEEE-754 style as
  * sign | exponent | fraction. FP32 is `FloatFormat(8, 23)`.
  *
  * This is the single place that names a format; every unit, width and
  * Verilog name derives from it. Encodings are IEEE-754 generalised to any
  * width: exponent field 0 is zero or subnormal, all ones is infinity or NaN.
  *
  * == Subnormal and NaN policy (the one place it is stated) ==
  *  - Subnormals are fully supported, as inputs and as results, by the golden
  *    model and by every unit. Reason: FP32 RNE must be bit-exact with JVM
  *    `Float` (and the C++ twins), and flushing would also break the directed
  *    rounding guarantee near zero (a flushed RUP result could be below the
  *    exact value).
  *  - Every NaN a unit or the model produces is the canonical quiet NaN
  *    [[canonicalNaN]]: sign 0, exponent all ones, fraction MSB 1, rest 0.
  *    NaN payloads carry no meaning in a ray tracer, and one NaN makes results
  *    comparable bit for bit. Tests compare with JVM results after mapping
  *    every NaN to the canonical one, i.e. `Float.floatToIntBits` semantics
  *    ("all NaNs are equal"); see [[FpModel.f32Bits]].
  *  - No exception flags are produced; signalling NaNs behave as quiet ones.
  */
case class FloatFormat(expBits: Int, manBits: Int) {
  require(expBits >= 3 && expBits <= 11, s"FloatFormat: expBits must be in 3..11, got $expBits")
  require(manBits >= 2 && manBits <= 52, s"FloatFormat: manBits must be in 2..52, got $manBits")

  /** Total encoded width in bits. */
  val width: Int = 1 + expBits + manBits

  /** Exponent bias, as in IEEE-754. */
  val bias: Int = (1 << (expBits - 1)) - 1

  /** Significand precision including the hidden bit. */
  val precision: Int = manBits + 1

  /** Exponent field of infinities and NaNs (all ones). */
  val maxExpField: Int = (1 << expBits) - 1

  /** Unbiased exponent of the smallest normal number (and of all subnormals). */
  val emin: Int = 1 - bias

  /** Unbiased exponent of the largest finite number. */
  val emax: Int = bias

  /** Stable short name for Verilog module names and reports, e.g. `e8m23`. */
  val name: String = s"e${expBits}m$manBits"

  private val fracMask: BigInt = (BigInt(1) << manBits) - 1
  private val allBits: BigInt = (BigInt(1) << width) - 1

  // ---- encoding ----
  def pack(sign: Boolean, expField: Int, frac: BigInt): BigInt = {
    require(expField >= 0 && expField <= maxExpField, s"$name: exponent field $expField out of range")
    require(frac >= 0 && frac <= fracMask, s"$name: fraction $frac out of range")
    (if (sign) BigInt(1) << (width - 1) else BigInt(0)) | (BigInt(expField) << manBits) | frac
  }
  def zero(sign: Boolean): BigInt = pack(sign, 0, 0)
  def infinity(sign: Boolean): BigInt = pack(sign, maxExpField, 0)
  def maxFinite(sign: Boolean): BigInt = pack(sign, maxExpField - 1, fracMask)
  def minNormal(sign: Boolean): BigInt = pack(sign, 1, 0)
  def maxSubnormal(sign: Boolean): BigInt = pack(sign, 0, fracMask)
  def minSubnormal(sign: Boolean): BigInt = pack(sign, 0, 1)
  def one(sign: Boolean): BigInt = pack(sign, bias, 0)

  /** The only NaN units and model ever produce (see the NaN policy above). */
  val canonicalNaN: BigInt = pack(sign = false, maxExpField, BigInt(1) << (manBits - 1))

  // ---- decoding and classification ----
  def checkBits(bits: BigInt): BigInt = {
    require(bits >= 0 && bits <= allBits, s"$name: bit pattern 0x${bits.toString(16)} does not fit in $width bits")
    bits
  }
  def sign(bits: BigInt): Boolean = bits.testBit(width - 1)
  def expField(bits: BigInt): Int = ((bits >> manBits) & maxExpField).toInt
  def frac(bits: BigInt): BigInt = bits & fracMask
  def negate(bits: BigInt): BigInt = bits.flipBit(width - 1)
  def abs(bits: BigInt): BigInt = bits.clearBit(width - 1)

  def isNaN(bits: BigInt): Boolean = expField(bits) == maxExpField && frac(bits) != 0
  def isInfinite(bits: BigInt): Boolean = expField(bits) == maxExpField && frac(bits) == 0
  def isZero(bits: BigInt): Boolean = expField(bits) == 0 && frac(bits) == 0
  def isSubnormal(bits: BigInt): Boolean = expField(bits) == 0 && frac(bits) != 0
  def isNormal(bits: BigInt): Boolean = { val e = expField(bits); e != 0 && e != maxExpField }
  def isFinite(bits: BigInt): Boolean = expField(bits) != maxExpField
  def classify(bits: BigInt): FpClass = {
    checkBits(bits)
    if (isNaN(bits)) FpClass.NaN
    else if (isInfinite(bits)) FpClass.Infinity
    else if (isZero(bits)) FpClass.Zero
    else if (isSubnormal(bits)) FpClass.Subnormal
    else FpClass.Normal
  }

  /** Significand including the hidden bit (an integer), for a finite value. */
  def significand(bits: BigInt): BigInt =
    if (expField(bits) == 0) frac(bits) else frac(bits).setBit(manBits)

  /** Exponent of the significand's LSB: a finite value is `significand * 2^lsbExponent`. */
  def lsbExponent(bits: BigInt): Int = math.max(expField(bits), 1) - bias - manBits

  override def toString: String = name
}

/** The five classes of an encoding. */
sealed trait FpClass
object FpClass {
  case object Zero extends FpClass
  case object Subnormal extends FpClass
  case object Normal extends FpClass
  case object Infinity extends FpClass
  case object NaN extends FpClass
}

object FloatFormat {
  val FP32: FloatFormat = FloatFormat(8, 23)
  val FP64: FloatFormat = FloatFormat(11, 52)

  /** Parses `e8m23`-style names, as used by `make regress FLOAT=...`. */
  def parse(s: String): FloatFormat = {
    val Pattern = """e(\d+)m(\d+)""".r
    s.trim match {
      case Pattern(e, m) => FloatFormat(e.toInt, m.toInt)
      case other         => throw new IllegalArgumentException(s"not a float format: '$other' (expected e.g. e8m23)")
    }
  }
}
