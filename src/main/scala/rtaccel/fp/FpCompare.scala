package rtaccel.fp

import chisel3._
import chisel3.util._

/** Results of comparing `a` with `b`. */
class FpCompareOut(val fmt: FloatFormat) extends Bundle {

  /** IEEE a < b (false when unordered; -0 < +0 is false). */
  val lt = Bool()

  /** IEEE a == b (false when unordered; -0 == +0). */
  val eq = Bool()

  /** Either operand is NaN. */
  val unordered = Bool()

  /** minimumNumber(a, b): a NaN loses; -0 < +0; NaN only if both are NaN. */
  val min = UInt(fmt.width.W)

  /** maximumNumber(a, b), same rules. */
  val max = UInt(fmt.width.W)
}

/** Comparator with min and max (IEEE 754-2019 minimumNumber/maximumNumber, as
  * [[FpModel.min]]): a NaN operand loses, so a NaN slab distance in the box
  * test never shrinks the interval. No rounding, so no mode. `latency`
  * registers sit at the output.
  */
class FpCompare(val fmt: FloatFormat, val latency: Int = FpCompare.defaultLatency) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, dynamicRm = false), new FpCompareOut(fmt)))
  override def desiredName: String = s"FpCompare_${fmt.name}_l$latency"

  private val (a, b) = (io.in.bits.a, io.in.bits.b)
  private val ua = FpUnpack(fmt, a)
  private val ub = FpUnpack(fmt, b)

  /** Maps sign-magnitude to an unsigned order in which -0 sits just below +0. */
  private def key(x: UInt): UInt = {
    val s = x(fmt.width - 1)
    Mux(s, ~x, x | (BigInt(1) << (fmt.width - 1)).U)
  }
  private val aBelowOrSame = key(a) <= key(b)
  private val bothZero = ua.isZero && ub.isZero
  private val unordered = ua.isNaN || ub.isNaN
  private val nan = fmt.canonicalNaN.U(fmt.width.W)

  private val res = Wire(new FpCompareOut(fmt))
  res.unordered := unordered
  res.eq := !unordered && (a === b || bothZero)
  res.lt := !unordered && key(a) < key(b) && !bothZero
  res.min := MuxCase(Mux(aBelowOrSame, a, b), Seq((ua.isNaN && ub.isNaN) -> nan, ua.isNaN -> b, ub.isNaN -> a))
  res.max := MuxCase(Mux(aBelowOrSame, b, a), Seq((ua.isNaN && ub.isNaN) -> nan, ua.isNaN -> b, ub.isNaN -> a))
  io.out := Pipe(io.in.valid, res, latency)
}

object FpCompare {
  val defaultLatency: Int = 1
}
