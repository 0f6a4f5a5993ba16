package rtaccel.fp

/** A binary floating-point format with `expBits` exponent bits and `manBits`
  * stored mantissa (fraction) bits, laid out IEEE-754 style as
  * sign | exponent | fraction. FP32 is `FloatFormat(8, 23)`.
  *
  * This is the single place that names a format; every unit, width and
  * Verilog name derives from it.
  */
case class FloatFormat(expBits: Int, manBits: Int) {
  require(expBits >= 3 && expBits <= 11, s"FloatFormat: expBits must be in 3..11, got $expBits")
  require(manBits >= 2 && manBits <= 52, s"FloatFormat: manBits must be in 2..52, got $manBits")

  /** Total encoded width in bits. */
  val width: Int = 1 + expBits + manBits
  /** Exponent bias, as in IEEE-754. */
  val bias: Int = (1 << (expBits - 1)) - 1
  /** Stable short name for Verilog module names and reports, e.g. `e8m23`. */
  val name: String = s"e${expBits}m$manBits"

  override def toString: String = name
}

object FloatFormat {
  val FP32: FloatFormat = FloatFormat(8, 23)

  /** Parses `e8m23`-style names, as used by `make regress FLOAT=...`. */
  def parse(s: String): FloatFormat = {
    val Pattern = """e(\d+)m(\d+)""".r
    s.trim match {
      case Pattern(e, m) => FloatFormat(e.toInt, m.toInt)
      case other         => throw new IllegalArgumentException(s"not a float format: '$other' (expected e.g. e8m23)")
    }
  }
}
