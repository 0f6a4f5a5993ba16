package rtaccel.fp

import chisel3._
import chisel3.util._

/** Two operands of a format, plus the rounding mode when it is a runtime input. */
class FpBinaryIn(val fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  val a = UInt(fmt.width.W)
  val b = UInt(fmt.width.W)

  /** Runtime rounding mode ([[RoundingMode.code]]); present only for `rm = None` units. */
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}

/** One operand of format `fmt`, plus the rounding mode when it is a runtime input. */
class FpUnaryIn(val fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  val a = UInt(fmt.width.W)
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}

/** Valid-pipe interface of every unit: one operation in per cycle (II = 1),
  * its result out exactly `latency` cycles later. There is no back-pressure;
  * a consumer that can stall puts a queue after the unit.
  */
class FpUnitIO[I <: Data, O <: Data](inGen: I, outGen: O) extends Bundle {
  val in = Flipped(Valid(inGen))
  val out = Valid(outGen)
}

object FpUnitIO {

  /** The rounding-mode signal of a unit: the fixed mode, or its runtime port. */
  def roundingMode(fixed: Option[RoundingMode], port: Option[UInt]): UInt =
    fixed.map(_.code.U(RoundingMode.width.W)).getOrElse(port.get)

  /** Stable Verilog name, e.g. `FpAdd_e8m23_rne_l2` or `FpAdd_e8m23_dyn_l2`. */
  def name(unit: String, fmt: FloatFormat, rm: Option[RoundingMode], latency: Int): String =
    s"${unit}_${fmt.name}_${RoundingMode.tag(rm)}_l$latency"
}

/** One result rounded down (RDN) and up (RUP): a unit that rounds once per mode from one exact value. */
class FpDnUp(val fmt: FloatFormat) extends Bundle {
  val dn = UInt(fmt.width.W)
  val up = UInt(fmt.width.W)
}

object FpDnUp {

  /** The (mode, sign) pairs FpRound.inModes takes, RDN first, both with `sign`. */
  def modes(sign: Bool): Seq[(UInt, Bool)] = Seq(RoundingMode.RDN, RoundingMode.RUP).map(m => (m.code.U, sign))

  def apply(fmt: FloatFormat, rounded: Seq[UInt]): FpDnUp = {
    val o = Wire(new FpDnUp(fmt))
    o.dn := rounded(0)
    o.up := rounded(1)
    o
  }
}

/** One result rounded in two modes, `lo` and `hi` (a unit's fixed pair, e.g. [[FpRecipPair]]). */
class FpLoHi(val fmt: FloatFormat) extends Bundle {
  val lo = UInt(fmt.width.W)
  val hi = UInt(fmt.width.W)
}

object FpLoHi {
  def apply(fmt: FloatFormat, rounded: Seq[UInt]): FpLoHi = {
    val o = Wire(new FpLoHi(fmt))
    o.lo := rounded(0)
    o.hi := rounded(1)
    o
  }
}
