package rtaccel.fp

import chisel3._
import chisel3.util._

/** The adder's exact sum before rounding ([[FpAdd.front]]): `(-1)^sign * (sig + d) * 2^e` with `d` as in
  * [[FpRaw]], where the biased exponent of `sig`'s MSB is `bigExp + 1` (`bigExp`: the larger operand's
  * exponent field, 1 for a subnormal). The sign is the larger operand's (`bigSign`) unless the sum is an
  * infinity (`infSign`) or an exact zero of an effective subtraction (its sign depends on the mode); the
  * normaliser picks it ([[FpAddNorm]]).
  */
class FpAddMid(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  val isNaN = Bool()
  val isInf = Bool()
  val infSign = Bool()
  val bigSign = Bool()
  val effSub = Bool()
  val sig = UInt(FpAddNorm.width(fmt).W)
  val sticky = Bool()
  val bigExp = UInt(fmt.expBits.W)
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}

/** The adder's normaliser, in place of [[FpRound]]'s first stages (the last two, the rounding decision and
  * the encoding, are [[FpRound.finish]]).
  *
  * A sum's exponent is never below the smaller operand's, so its value lies on the subnormal grid and one
  * left shift, stopped at the grid, normalises every result: no right shifter (FpRound's fast path).
  * Exponents here are the format's biased exponent fields, not FpRound's wide signed LSB exponents: the
  * MSB's exponent is bigExp + 1, the result's bigExp + 1 - min(lz, bigExp) in [1, 2^expBits], so
  * expBits + 2 signed bits hold every value and every exponent chain and compare is that narrow.
  */
object FpAddNorm {

  /** The sum's width: the significand, FpAdd.extra bits below it, and the carry out of an addition. */
  def width(fmt: FloatFormat): Int = fmt.precision + FpAdd.extra + 1

  /** After the leading-zero count, after the shift amount, after the shift, and FpRound.finish's one. */
  val cuts: Int = 4

  /** `mid` rounded in each of `modes` (literals, or the one runtime mode carried in `mid.rm`). */
  def apply(fmt: FloatFormat, mid: FpAddMid, modes: Seq[UInt], stages: FpStages): Seq[UInt] = {
    val p = fmt.precision
    val w = width(fmt)
    val ew = fmt.expBits + 2
    def state = new FpRound.State(w, p, ew, log2Ceil(w), mid.rm.isDefined, modes.size)

    // Stage 1: the leading zeros; the MSB's exponent, one less and one more, beside the count.
    val s0 = Wire(state)
    s0 := DontCare
    s0.rm.foreach(_ := mid.rm.get)
    s0.isNaN := mid.isNaN
    s0.isInf := mid.isInf
    // A sig of 0 is an exact zero: a difference with sticky set is never 0 (sticky needs the exponents
    // extra + 1 or more apart, so the larger operand is normal, its significand with the extra bits is at
    // least 2^(p + extra - 1) and the aligned smaller one below 2^(p - 1)), and a sum with sticky set has a
    // nonzero smaller operand. Tested on the registered sum beside the leading-zero count.
    val zero = mid.sig === 0.U
    s0.zero := zero
    // Exact zero: (-0)+(-0) = -0 (the larger operand's sign), x+(-x) = +0 except -0 in RDN (IEEE 754 6.3).
    for ((m, j) <- modes.zipWithIndex)
      s0.sign(j) := MuxCase(
        mid.bigSign,
        Seq(mid.isInf -> mid.infSign, (zero && mid.effSub) -> (m === RoundingMode.RDN.code.U))
      )
    s0.sticky := mid.sticky
    s0.sig := mid.sig
    s0.lz := FpUnpack.leadingZeros(mid.sig) // a sig of 0 is flagged apart
    s0.eTop := (mid.bigExp +& 1.U).zext.pad(ew)
    s0.eTopM1 := mid.bigExp.zext.pad(ew)
    s0.eTopP1 := (mid.bigExp +& 2.U).zext.pad(ew)
    val s1 = stages(s0)

    // Stage 2: tiny (the shift would pass the grid: lz > eTop - 1), and the shift amount, stopped at the grid
    // (eTop - 1 when tiny); both exponent candidates beside the compare. After a stop at the grid the
    // exponent is 1, and a top bit of 0 after rounding encodes a subnormal (FpRound.finish).
    val s2 = Wire(state)
    s2 := s1
    val lzS = s1.lz.zext.pad(ew)
    s2.tiny := s1.eTopM1 < lzS
    s2.biasedExp := s1.eTop - lzS
    s2.biasedExpP1 := s1.eTopP1 - lzS
    s2.lz := Mux(s2.tiny, s1.eTopM1.asUInt(log2Ceil(w) - 1, 0), s1.lz)
    val s3 = stages(s2)

    // Stage 3: the shift by the registered amount. (The compare, the select and the shifter in one cycle were
    // 5.73 ns, even with both shifts made and `tiny` picking one: the mapper merges them.)
    val s4 = Wire(state)
    s4 := s3
    // A shift of 3 or more never moves the sum's two lowest bits into the window: the sum then has 3 or more
    // leading zeros, which needs operands at most one exponent apart (d <= 1). With the larger operand normal
    // (as it is for d >= 1), a sum is at least its significand 2^(p+2) (with the extra bits: at most 1 leading
    // zero), and for d >= 2 a difference exceeds 2^(p+2) - 2^(p+1) (at most 2). For d <= 1 the aligned operand
    // is shifted by at most one of its FpAdd.extra bits, so its two lowest bits are 0 and there is no sticky
    // bit: the sum's or difference's two lowest bits are 0 too.
    val low = Mux(s3.lz < 3.U, s3.sig(1, 0), 0.U(2.W))
    s4.window := (Cat(s3.sig(w - 1, 2), low) << s3.lz)(w - 1, w - p - 2)
    s4.tail := FpRound.below(s3.sig, p, s3.lz) || s3.sticky
    FpRound.finish(fmt, stages(s4), modes, Some(stages))
  }
}
