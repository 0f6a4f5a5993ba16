package rtaccel.fp

import chisel3._
import chisel3.util._

/** One step of the divider pipeline: partial remainder, quotient bits so far,
  * and what the rounder needs later.
  */
class FpDivState(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  private val p = fmt.precision

  /** Partial remainder; always < 2 * divisor. */
  val rem = UInt((p + 1).W)
  val divisor = UInt(p.W)
  val quo = UInt((p + 2).W)
  val meta = new FpRawStage(p + 2, FpUnpack.expWidth(fmt) + 2, dynamicRm)

  /** The normalising shifts' leading-zero counts, read (into `meta.raw.exp`) by the first step only. */
  val lzA = UInt(log2Ceil(p).W)
  val lzB = UInt(log2Ceil(p).W)
}

/** Correctly rounded division by radix-2 restoring digit recurrence.
  *
  * Both significands are normalised to [2^(p-1), 2^p) (subnormals by a
  * leading-zero shift), so A/B lies in (1/2, 2). `p + 2` recurrence steps give
  * Q = floor(A * 2^(p+1) / B), which has p+1 or p+2 significant bits, and the
  * final remainder says whether the quotient is exact (the sticky bit). One
  * [[FpRound]] then rounds Q + sticky in the mode (or in several modes,
  * [[inModes]]), so every mode is correctly rounded (not just faithfully, as
  * a Newton-Raphson estimate without a remainder correction would be).
  *
  * Pipelining: cut points after the leading-zero counts, after the normalising shifts, after each recurrence step,
  * the rounder's, and at the output share the `latency` registers evenly
  * ([[FpPipeline]]). Each step is one (p+1)-bit compare-subtract, i.e. one
  * carry chain and a mux. The normalisation stage only counts and shifts:
  * the quotient's exponent takes the leading-zero counts in the first step
  * (beside its compare-subtract), so no exponent carry chain waits on a count
  * in the stage an operand enters (an operand mux in front of the unit, as in
  * RayPrep's shear, lands on that stage).
  */
object FpDivCore {
  def cuts(fmt: FloatFormat): Int = 2 + (fmt.precision + 2) + FpRound.cuts(fmt, fmt.precision + 2) + 1

  /** One register per cut point: one recurrence step per cycle (docs/fmax.md). */
  def defaultLatency(fmt: FloatFormat): Int = cuts(fmt)

  /** Builds the divider for dividend `a` and divisor `b` (bits of `fmt`), rounded in `rm`. */
  def apply(
      fmt: FloatFormat,
      rm: Option[RoundingMode],
      latency: Int,
      valid: Bool,
      a: UInt,
      b: UInt,
      rmPort: Option[UInt]
  ): Valid[UInt] = inModes(fmt, latency, valid, a, b, rmPort, r => Seq(FpUnitIO.roundingMode(rm, r)))(_.head)

  /** The divider with one recurrence and one normaliser, its quotient rounded
    * in each of the modes `modesOf` gives from the carried runtime mode (if
    * any; FpRound.inModes), each result the bits the single-mode divider
    * gives; `pack` makes the output of the results (in that order).
    */
  def inModes[T <: Data](
      fmt: FloatFormat,
      latency: Int,
      valid: Bool,
      a: UInt,
      b: UInt,
      rmPort: Option[UInt],
      modesOf: Option[UInt] => Seq[UInt]
  )(pack: Seq[UInt] => T): Valid[T] = {
    val p = fmt.precision
    val dynamicRm = rmPort.isDefined
    val pipe = new FpPipeline(latency, cuts(fmt))
    val ua = FpUnpack(fmt, a)
    val ub = FpUnpack(fmt, b)
    // Normalisation in two cut points: the leading-zero counts, then the shifts by them (a count and the shift
    // behind it in one stage were the 3-mode reciprocal's longest path, docs/fmax.md).
    def lz(u: FpUnpacked): UInt = FpUnpack.leadingZeros(u.sig) // a zero operand is flagged apart

    val s0 = Wire(new FpDivState(fmt, dynamicRm))
    val raw = s0.meta.raw
    s0.meta.rm.foreach(_ := rmPort.get)
    raw.isNaN := ua.isNaN || ub.isNaN || (ua.isZero && ub.isZero) || (ua.isInf && ub.isInf)
    raw.isInf := ua.isInf || ub.isZero
    raw.isZero := ua.isZero || ub.isInf
    raw.sign := ua.sign ^ ub.sign
    // Q has weight 2^-(p+1) relative to A/B; the normalised exponents are (ua.exp - lzA) and
    // (ub.exp - lzB), whose counts the first step adds (the same integer, no wrap in either width).
    raw.exp := ua.exp -& ub.exp -& (p + 1).S
    raw.sig := DontCare
    raw.sticky := DontCare
    s0.rem := ua.sig
    s0.divisor := ub.sig
    s0.quo := 0.U
    s0.lzA := lz(ua)
    s0.lzB := lz(ub)
    val counted = pipe.cut(valid, s0)
    val s1 = Wire(new FpDivState(fmt, dynamicRm))
    s1 := counted.bits
    s1.rem := FpUnpack.shiftLeftMsbFirst(counted.bits.rem(p - 1, 0), counted.bits.lzA)
    s1.divisor := FpUnpack.shiftLeftMsbFirst(counted.bits.divisor, counted.bits.lzB)

    var stage = pipe.cut(counted.valid, s1)
    for (i <- 0 until p + 2) {
      val s = stage.bits
      val next = Wire(new FpDivState(fmt, dynamicRm))
      next := s
      if (i == 0) {
        next.meta.raw.exp := s.meta.raw.exp - s.lzA.zext + s.lzB.zext
        next.lzA := DontCare
        next.lzB := DontCare
      }
      val fits = s.rem >= s.divisor
      val left = Mux(fits, s.rem - s.divisor, s.rem) // < divisor < 2^p
      next.rem := left << 1
      next.quo := Cat(s.quo(p, 0), fits)
      stage = pipe.cut(stage.valid, next)
    }
    val last = WireInit(stage.bits.meta)
    last.raw.sig := stage.bits.quo
    last.raw.sticky := stage.bits.rem =/= 0.U
    roundQuotient(fmt, pipe, stage.valid, last, modesOf)(pack)
  }

  /** A quotient and its sticky bit (`last`, p + 2 bits) through the rounder's cuts, rounded in each of the modes
    * `modesOf` gives, and the output cut: the back half the divider and the reciprocal ([[FpRecipCore]]) share.
    */
  def roundQuotient[T <: Data](
      fmt: FloatFormat,
      pipe: FpPipeline,
      valid: Bool,
      last: FpRawStage,
      modesOf: Option[UInt] => Seq[UInt]
  )(pack: Seq[UInt] => T): Valid[T] = {
    val stages = new FpStages(pipe, valid)
    // A quotient's sign is the same in every mode (no exact zero depends on the mode).
    val modes = modesOf(last.rm).map(m => (m, last.raw.sign))
    // Rounded first: its cuts advance `stages.valid`.
    val rounded = FpRound.inModes(fmt, last.raw, modes, None, Some(stages))
    val out = pipe.cut(stages.valid, pack(rounded))
    pipe.done()
    out
  }
}

/** Divider `a / b`, correctly rounded in every mode (see [[FpDivCore]]). */
class FpDiv(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int) extends Module {
  def this(fmt: FloatFormat, rm: Option[RoundingMode]) = this(fmt, rm, FpDivCore.defaultLatency(fmt))
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name("FpDiv", fmt, rm, latency)
  io.out := FpDivCore(fmt, rm, latency, io.in.valid, io.in.bits.a, io.in.bits.b, io.in.bits.rm)
}

/** Reciprocal `1 / a`, correctly rounded in every mode, on the DSP48s ([[FpRecipCore]]): bit for bit the
  * divider's `1 / a`.
  */
class FpRecip(val fmt: FloatFormat, val rm: Option[RoundingMode], val latency: Int) extends Module {
  def this(fmt: FloatFormat, rm: Option[RoundingMode]) = this(fmt, rm, FpRecipCore.defaultLatency(fmt))
  val io = IO(new FpUnitIO(new FpUnaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name("FpRecip", fmt, rm, latency)
  io.out := FpRecipCore.inModes(
    fmt,
    latency,
    io.in.valid,
    io.in.bits.a,
    io.in.bits.rm,
    r =>
      Seq(FpUnitIO.roundingMode(rm, r))
  )(_.head)
}

/** Reciprocal `1 / a` rounded in two fixed modes, `lo` and `hi`, from one
  * estimate and one normaliser ([[FpRecipCore.inModes]]): each result is bit
  * for bit [[FpRecip]]'s in that mode; same cuts and latency.
  */
class FpRecipPair(val fmt: FloatFormat, val lo: RoundingMode, val hi: RoundingMode, val latency: Int)
    extends Module {
  def this(fmt: FloatFormat, lo: RoundingMode, hi: RoundingMode) =
    this(fmt, lo, hi, FpRecipCore.defaultLatency(fmt))
  val io = IO(new FpUnitIO(new FpUnaryIn(fmt, false), new FpLoHi(fmt)))
  override def desiredName: String = s"FpRecipPair_${fmt.name}_${lo.name}_${hi.name}_l$latency"
  private val modes = Seq(lo, hi).map(_.code.U(RoundingMode.width.W))
  io.out := FpRecipCore.inModes(fmt, latency, io.in.valid, io.in.bits.a, None, _ => modes)(FpLoHi(fmt, _))
}

/** Reciprocal `1 / a` rounded in each of `modes` (fixed, at least one) from
  * one estimate and one normaliser, as [[FpRecipPair]]: each result is bit
  * for bit [[FpRecip]]'s in that mode; same cuts and latency. RayPrep takes
  * |1/d| toward zero, up and to nearest from one unit per axis: the box
  * lanes' two bounds and the watertight shear's 1/d[kz] (RNE is
  * sign-symmetric, so the magnitude's result negated is 1/d's).
  */
class FpRecipModes(val fmt: FloatFormat, val modes: Seq[RoundingMode], val latency: Int) extends Module {
  require(modes.nonEmpty && modes.distinct == modes, s"FpRecipModes: modes $modes must be distinct and not empty")
  def this(fmt: FloatFormat, modes: Seq[RoundingMode]) = this(fmt, modes, FpRecipCore.defaultLatency(fmt))
  val io = IO(new FpUnitIO(new FpUnaryIn(fmt, false), Vec(modes.size, UInt(fmt.width.W))))
  override def desiredName: String = s"FpRecip_${fmt.name}_${modes.map(_.name).mkString("_")}_l$latency"
  private val codes = modes.map(_.code.U(RoundingMode.width.W))
  io.out := FpRecipCore.inModes(fmt, latency, io.in.valid, io.in.bits.a, None, _ => codes)(VecInit(_))
}
