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
  io.out := Pipe(io.in.valid, FpCompare.logic(fmt, io.in.bits.a, io.in.bits.b), latency)
}

object FpCompare {
  val defaultLatency: Int = 1

  /** The comparator's logic, unregistered. The datapaths build it in place
    * (HwArith), not as a module, so that synthesis keeps only the outputs a
    * use reads: a box lane's `le` needs no min/max muxes, and a min against
    * a constant infinity folds.
    */
  def logic(fmt: FloatFormat, a: UInt, b: UInt): FpCompareOut = {
    val ua = FpUnpack(fmt, a)
    val ub = FpUnpack(fmt, b)

    // The order of sign-magnitude patterns in which -0 sits just below +0 (the unsigned order of `s ? ~x :
    // x | msb`), from the magnitudes' two compares and the signs: different signs order by sign, two negative
    // values by reversed magnitude. The compares read the registers directly (with that key mux in front of
    // one compare, and the min's select behind it, a box lane's fold of mins was 5.67 ns).
    val (sa, sb) = (a(fmt.width - 1), b(fmt.width - 1))
    val aMagLe = a(fmt.width - 2, 0) <= b(fmt.width - 2, 0)
    val bMagLe = b(fmt.width - 2, 0) <= a(fmt.width - 2, 0)
    val aBelowOrSame = Mux(sa =/= sb, sa, Mux(sa, bMagLe, aMagLe))
    val aBelow = Mux(sa =/= sb, sa, Mux(sa, !aMagLe, !bMagLe))
    val bothZero = ua.isZero && ub.isZero
    val unordered = ua.isNaN || ub.isNaN
    val nan = fmt.canonicalNaN.U(fmt.width.W)

    val res = Wire(new FpCompareOut(fmt))
    res.unordered := unordered
    res.eq := !unordered && (a === b || bothZero)
    res.lt := !unordered && aBelow && !bothZero
    res.min := MuxCase(Mux(aBelowOrSame, a, b), Seq((ua.isNaN && ub.isNaN) -> nan, ua.isNaN -> b, ub.isNaN -> a))
    res.max := MuxCase(Mux(aBelowOrSame, b, a), Seq((ua.isNaN && ub.isNaN) -> nan, ua.isNaN -> b, ub.isNaN -> a))
    res
  }
}
