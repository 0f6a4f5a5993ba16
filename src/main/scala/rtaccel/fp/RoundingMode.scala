package rtaccel.fp

/** IEEE-754 rounding direction. `code` is the value of a unit's runtime `rm`
  * port (2 bits, [[RoundingMode.width]]); `name` goes into Verilog names.
  *
  *  - RNE: to nearest, ties to even (IEEE default; JVM `Float` arithmetic).
  *  - RTZ: toward zero (truncation).
  *  - RDN: toward -inf. Used for lower box bounds: the result is <= exact.
  *  - RUP: toward +inf. Used for upper box bounds: the result is >= exact.
  */
sealed abstract class RoundingMode(val code: Int, val name: String) {
  override def toString: String = name
}

object RoundingMode {
  case object RNE extends RoundingMode(0, "rne")
  case object RTZ extends RoundingMode(1, "rtz")
  case object RDN extends RoundingMode(2, "rdn")
  case object RUP extends RoundingMode(3, "rup")

  val all: Seq[RoundingMode] = Seq(RNE, RTZ, RDN, RUP)

  /** Width of a runtime rounding-mode port. */
  val width: Int = 2

  def fromCode(code: Int): RoundingMode =
    all.find(_.code == code).getOrElse(throw new IllegalArgumentException(s"no rounding mode with code $code"))

  /** Verilog-name tag for a unit: the fixed mode, or `dyn` for a runtime port. */
  def tag(rm: Option[RoundingMode]): String = rm.map(_.name).getOrElse("dyn")
}
