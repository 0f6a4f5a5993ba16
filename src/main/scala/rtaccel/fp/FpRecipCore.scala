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

  /** The partials of the product being formed (DspMul), for the widest of `b y`, `y E'` and `Qc B`. */
  val dsp = new DspPartials(
    p + 1,
    (plan.steps.flatMap(st => Seq(st.fIn + 2, st.eWidth + 1)) :+ (p + 3)).max
  )

  /** The current step's error term `E'`, plus 2^(eWidth-1), and `y 2^(fOut-fIn+shift) - y 2^(eWidth-1)`. */
  val e = UInt(eWidth.W)
  val w = SInt((1 +: plan.steps.map(st => st.fOut + 3 + st.productShift(p))).max.W)

  /** The estimate `Qc` (within one of the quotient) and the remainder `R`. */
  val qc = UInt((p + 2).W)
  val r = SInt((p + 3).W)

  /** `-B` modulo 2^(p+3), formed once `B` is normalised. */
  val negB = UInt((p + 3).W)

  /** `R = -B`, `R = B` and `R = 0`, tested beside the chain that forms `R`. */
  val rIsNegB = Bool()
  val rIsB = Bool()
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
  * table; per Newton step the product `b y` on DSP48s ([[DspMul]]: a cut per
  * DSP48 and one after the last sum), the error term `2^(p-1+f) - b y` (one
  * carry chain), the product `y E'` on DSP48s, the sum `y + y E'` (one carry
  * chain); the estimate's product `Qc B` (DSP48s), the remainder `-Qc B` (one
  * chain, its equality tests with `-B` and 0 beside it), its other tests and
  * `Qc +- 1` (chains side by side), the corrected quotient (a select); the
  * rounder's four; the output. Each product's operands are registers (the
  * DSP48s' input registers).
  * FP32: 2 Newton steps, 27 cut points, against the recurrence's 33.
  */
object FpRecipCore {
  def plan(fmt: FloatFormat): FpRecipPlan = FpRecipPlan(fmt.precision)

  def cuts(fmt: FloatFormat): Int = {
    val p = fmt.precision
    val steps = plan(fmt).steps.map(st => DspMul.cuts(st.fIn + 2) + 1 + DspMul.cuts(st.eWidth + 1) + 1).sum
    3 + steps + DspMul.cuts(p + 3) + 3 + FpRound.cuts(fmt, p + 2) + 1
  }

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
    // The product `a b` of the stage's registers (which the product's stages carry unchanged), after its cuts.
    def product(a: FpRecipState => SInt, b: FpRecipState => SInt): SInt = {
      for (s <- 1 to DspMul.cuts(b(stage.bits).getWidth)) {
        val n = next(stage.bits)
        n.dsp := DspMul.step(s, a(stage.bits), b(stage.bits), stage.bits.dsp)
        cut(stage.valid, n)
      }
      DspMul.result(a(stage.bits), b(stage.bits), stage.bits.dsp)
    }

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
    // (1 - p) - ub.exp - (p + 1) is one constant minus the LSB's exponent field, one carry chain (formed from
    // ub.exp, two chains, 5.06 ns).
    val expField = a(fmt.width - 2, fmt.manBits)
    val lsbField = Mux(expField === 0.U, 1.U, expField).zext
    val ew = raw.exp.getWidth
    raw.exp := (fmt.bias + fmt.manBits - 2 * p).S(ew.W) - lsbField.pad(ew)
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
    s2.negB := 0.U((p + 3).W) - stage.bits.b
    cut(stage.valid, s2)

    for (st <- pl.steps) {
      val by = product(_.b.zext, _.y(st.fIn, 0).zext).asUInt

      // E = 2^(p-1+f) - b y, floored by `drop` bits; FpRecipPlan bounds it to eWidth signed bits. It is kept
      // offset by 2^(eWidth-1), unsigned (the MSB flipped), so that `y E'` is an unsigned product: firtool
      // writes a signed one as an unsigned multiply of sign-extended operands, which Yosys splits over
      // DSP48s without registers. The offset's product `y 2^(eWidth-1)` is taken off `w` beside the chain.
      val a1 = next(stage.bits)
      val eFull = ((BigInt(1) << (p - 1 + st.fIn)).S((p + st.fIn + 3).W) - by(p + st.fIn, 0).zext) >> st.drop
      a1.e := eFull(st.eWidth - 1, 0) ^ (BigInt(1) << (st.eWidth - 1)).U
      val shift = st.productShift(p)
      val y = stage.bits.y(st.fIn, 0).zext
      a1.w := (y << (st.fOut - st.fIn + shift)) - (y << (st.eWidth - 1))
      a1.dsp := DontCare
      cut(stage.valid, a1)

      val z = product(_.y(st.fIn, 0).zext, _.e(st.eWidth - 1, 0).zext).asUInt

      // y' = y 2^(fOut-fIn) + floor(y E' / 2^shift) = floor((w + y (E' + 2^(eWidth-1))) / 2^shift), as w is
      // y 2^(fOut-fIn) 2^shift - y 2^(eWidth-1); in [0, 2^(fOut+1)) (FpRecipPlan).
      val a3 = next(stage.bits)
      val sum = (stage.bits.w +& z.zext) >> shift
      a3.y := sum(st.fOut, 0)
      a3.e := DontCare
      a3.w := DontCare
      a3.dsp := DontCare
      cut(stage.valid, a3)
    }

    // Qc = floor(y 2^(p+1)), a slice of the estimate's register, and the low p + 3 bits of Qc B (the
    // remainder 2^(2p) - Qc B is 0 - Qc B there).
    def qcOf(s: FpRecipState): UInt = s.y(pl.fLast, pl.quotientShift)
    val low = product(_.b.zext, qcOf(_).zext).asUInt(p + 2, 0)

    // R = -low (mod 2^(p+3)); R = -B, R = B and R = 0 are tested here on `low`, beside the chain (low = B,
    // low = -B mod 2^(p+3) and low = 0), so the next stage selects registered tests (below).
    val c1 = next(stage.bits)
    c1.qc := qcOf(stage.bits)
    c1.r := (0.U((p + 3).W) - low).asSInt
    c1.rIsNegB := low === stage.bits.b
    c1.rIsB := low === stage.bits.negB
    c1.rIsZero := low === 0.U
    c1.y := DontCare
    c1.dsp := DontCare
    cut(stage.valid, c1)

    // |R| < 2B: one correction either way. Each test and Qc +- 1 is its own carry chain or compare.
    val c2 = next(stage.bits)
    val r = stage.bits.r
    val bS = stage.bits.b.zext
    val under = r < 0.S
    val over = r >= bS
    c2.under := under
    c2.over := over
    // The equality tests come registered: with them behind the selects by `under` and `over`, this stage was
    // the reciprocal's longest path (R = B alone there: `over`'s chain and the compare into the select,
    // 5.67 ns in PrimIntersect).
    c2.exact := Mux(under, stage.bits.rIsNegB, Mux(over, stage.bits.rIsB, stage.bits.rIsZero))
    c2.qcDown := stage.bits.qc - 1.U
    c2.qcUp := stage.bits.qc + 1.U
    c2.r := DontCare
    c2.rIsNegB := DontCare
    c2.rIsB := DontCare
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
