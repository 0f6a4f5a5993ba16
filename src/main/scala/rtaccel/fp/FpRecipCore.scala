package rtaccel.fp

import chisel3._
import chisel3.util._

/** What the reciprocal's pipeline carries from cut to cut; fields not yet computed, or no longer read, are
  * DontCare (synthesis drops their registers).
  */
class FpRecipState(fmt: FloatFormat, plan: FpRecipPlan, dynamicRm: Boolean) extends Bundle {
  private val p = fmt.precision
  private val yWidth = (plan.tableBits +: plan.steps.map(_.fOut)).max + 1
  private val eWidth = (1 +: plan.steps.map(_.eWidth)).max
  val meta = new FpRawStage(p + 2, FpUnpack.expWidth(fmt) + 2, dynamicRm)
  val lz = UInt(log2Ceil(p).W)

  /** The divisor's significand, normalised to [2^(p-1), 2^p) from the table stage on. */
  val b = UInt(p.W)
  val y = UInt(yWidth.W)

  /** `b y` of the current step, then its error term `E'`, then `y E'`. */
  val prod = UInt((p + yWidth).W)
  val e = SInt(eWidth.W)
  val z = SInt((yWidth + 1 + eWidth).W)

  /** The estimate `Qc` (within one of the quotient), its product's low bits, the remainder `R`. */
  val qc = UInt((p + 2).W)
  val low = UInt((p + 3).W)
  val r = SInt((p + 3).W)

  /** `R = -B` and `R = 0`, tested beside the chain that forms `R`. */
  val rIsNegB = Bool()
  val rIsZero = Bool()

  /** `R < 0`, `R >= B`, and whether the remainder after that correction is 0. */
  val under = Bool()
  val over = Bool()
  val exact = Bool()
  val qcDown = UInt((p + 2).W)
  val qcUp = UInt((p + 2).W)
}

/** Correctly rounded reciprocal on the DSP48s: the quotient bits and sticky
  * bit the digit recurrence ([[FpDivCore]]) would give, `Q = floor(2^(2p) /
  * B)` for the normalised significand `B`, computed by a table, Newton-Raphson
  * steps and one remainder correction ([[FpRecipPlan]], whose integer model
  * this hardware computes step for step), then rounded by the shared
  * [[FpRound]] in each mode. Each result is bit for bit what the recurrence
  * gives (and the model, `FpModel.recip`), subnormals, zeros, infinities and
  * NaNs included.
  *
  * Cut points, in order: the leading-zero count, the normalising shift, the
  * table; per Newton step four (the product `b y` on a DSP48, the error term
  * `2^(p-1+f) - b y` (one carry chain), the product `y E'` on a DSP48, the sum
  * `y + y E'` (one carry chain)); the estimate's product `Qc B` (DSP48), the
  * remainder `-Qc B` (one chain, its equality tests with `-B` and 0 beside
  * it), its other tests and `Qc +- 1` (chains side by side), the corrected
  * quotient (a select); the rounder's four; the output.
  * FP32: 2 Newton steps, 20 cut points, against the recurrence's 33.
  */
object FpRecipCore {
  def plan(fmt: FloatFormat): FpRecipPlan = FpRecipPlan(fmt.precision)

  def cuts(fmt: FloatFormat): Int =
    3 + 4 * plan(fmt).steps.size + 4 + FpRound.cuts(fmt, fmt.precision + 2) + 1

  /** One register per cut point. */
  def defaultLatency(fmt: FloatFormat): Int = cuts(fmt)

  /** `1 / a` rounded in each of the modes `modesOf` gives from the carried runtime mode (if any); `pack` makes
    * the output of the results, in that order.
    */
  def inModes[T <: Data](
      fmt: FloatFormat,
      latency: Int,
      valid: Bool,
      a: UInt,
      rmPort: Option[UInt],
      modesOf: Option[UInt] => Seq[UInt]
  )(pack: Seq[UInt] => T): Valid[T] = {
    val p = fmt.precision
    val pl = plan(fmt)
    val dynamicRm = rmPort.isDefined
    val pipe = new FpPipeline(latency, cuts(fmt))
    def next(s: FpRecipState): FpRecipState = { val n = Wire(new FpRecipState(fmt, pl, dynamicRm)); n := s; n }
    var stage: Valid[FpRecipState] = null
    def cut(v: Bool, s: FpRecipState): Unit = stage = pipe.cut(v, s)

    // Unpack and count: the dividend is 1 (significand 2^(p-1), LSB exponent 1 - p).
    val ub = FpUnpack(fmt, a)
    val s0 = Wire(new FpRecipState(fmt, pl, dynamicRm))
    s0 := DontCare
    val raw = s0.meta.raw
    s0.meta.rm.foreach(_ := rmPort.get)
    raw.isNaN := ub.isNaN
    raw.isInf := ub.isZero
    raw.isZero := ub.isInf
    raw.sign := ub.sign
    // Q has weight 2^-(p+1) relative to 1/b; the normalised exponent is ub.exp - lz, added in the table stage.
    raw.exp := (1 - p).S -& ub.exp -& (p + 1).S
    raw.sig := DontCare
    raw.sticky := DontCare
    s0.b := ub.sig
    s0.lz := FpUnpack.leadingZeros(ub.sig) // a zero operand is flagged apart
    cut(valid, s0)

    // The normalising shift (a count and its shift in one stage were a reciprocal's longest path, docs/fmax.md).
    val s1 = next(stage.bits)
    s1.b := FpUnpack.shiftLeftMsbFirst(stage.bits.b, stage.bits.lz)
    cut(stage.valid, s1)

    // The table, and the count into the exponent.
    val s2 = next(stage.bits)
    s2.meta.raw.exp := stage.bits.meta.raw.exp + stage.bits.lz.zext
    s2.lz := DontCare
    val rom = VecInit(pl.table.map(_.U((pl.tableBits + 1).W)))
    s2.y := rom(stage.bits.b(p - 2, p - 1 - pl.indexBits))
    cut(stage.valid, s2)

    for (st <- pl.steps) {
      val a0 = next(stage.bits)
      a0.prod := stage.bits.b * stage.bits.y(st.fIn, 0)
      cut(stage.valid, a0)

      // E = 2^(p-1+f) - b y, floored by `drop` bits; FpRecipPlan bounds it to eWidth signed bits.
      val a1 = next(stage.bits)
      val eFull = ((BigInt(1) << (p - 1 + st.fIn)).S((p + st.fIn + 3).W) - stage.bits.prod(p + st.fIn, 0).zext) >>
        st.drop
      a1.e := eFull(st.eWidth - 1, 0).asSInt
      a1.prod := DontCare
      cut(stage.valid, a1)

      val a2 = next(stage.bits)
      a2.z := stage.bits.y(st.fIn, 0).zext * stage.bits.e(st.eWidth - 1, 0).asSInt
      a2.e := DontCare
      cut(stage.valid, a2)

      // y' = y 2^(fOut-fIn) + floor(y E' / 2^shift), in [0, 2^(fOut+1)) (FpRecipPlan).
      val a3 = next(stage.bits)
      val sum = Cat(stage.bits.y(st.fIn, 0), 0.U((st.fOut - st.fIn).W)).zext + (stage.bits.z >> st.productShift(p))
      a3.y := sum(st.fOut, 0)
      a3.z := DontCare
      cut(stage.valid, a3)
    }

    // Qc = floor(y 2^(p+1)) and the low p + 3 bits of Qc B (the remainder 2^(2p) - Qc B is 0 - Qc B there).
    val c0 = next(stage.bits)
    val qc = stage.bits.y(pl.fLast, pl.quotientShift)
    c0.qc := qc
    c0.low := (qc * stage.bits.b)(p + 2, 0)
    c0.y := DontCare
    cut(stage.valid, c0)

    // R = -low (mod 2^(p+3)); R = -B and R = 0 are tested here on `low`, beside the chain (low = B and
    // low = 0), so the next stage selects registered tests (below).
    val c1 = next(stage.bits)
    c1.r := (0.U((p + 3).W) - stage.bits.low).asSInt
    c1.rIsNegB := stage.bits.low === stage.bits.b
    c1.rIsZero := stage.bits.low === 0.U
    c1.low := DontCare
    cut(stage.valid, c1)

    // |R| < 2B: one correction either way. Each test and Qc +- 1 is its own carry chain or compare.
    val c2 = next(stage.bits)
    val r = stage.bits.r
    val bS = stage.bits.b.zext
    val under = r < 0.S
    val over = r >= bS
    c2.under := under
    c2.over := over
    // Only R = B is compared here: with all three compares behind the selects by `under` and `over`, this
    // stage was the reciprocal's longest path, 9 cells (3 LUT, 6 MUXF), 5.00 ns.
    c2.exact := Mux(under, stage.bits.rIsNegB, Mux(over, r === bS, stage.bits.rIsZero))
    c2.qcDown := stage.bits.qc - 1.U
    c2.qcUp := stage.bits.qc + 1.U
    c2.r := DontCare
    c2.rIsNegB := DontCare
    c2.rIsZero := DontCare
    cut(stage.valid, c2)

    val c3 = next(stage.bits)
    val s = stage.bits
    c3.meta.raw.sig := Mux(s.under, s.qcDown, Mux(s.over, s.qcUp, s.qc))
    c3.meta.raw.sticky := !s.exact
    c3.b := DontCare
    c3.qc := DontCare
    c3.qcDown := DontCare
    c3.qcUp := DontCare
    cut(stage.valid, c3)

    FpDivCore.roundQuotient(fmt, pipe, stage.valid, stage.bits.meta, modesOf)(pack)
  }
}
