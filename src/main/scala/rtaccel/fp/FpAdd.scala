package rtaccel.fp

import chisel3._
import chisel3.util._

/** Floating-point adder (or subtractor, with `subtract`): `a + b` (`a - b`)
  * rounded once in the mode. Front: compare the magnitudes and swap; align
  * the smaller significand with guard/round/sticky bits (a product on
  * DSP48E1s, [[FpAlign]]); add or subtract; then [[FpAddNorm]] and the
  * rounder's last stages. Cut points ([[FpPipeline]]): after the swap, after
  * the alignment's multiplier, the product's ([[DspMul]]), after the aligned
  * significand, after the add, the normaliser's and rounder's, and the output;
  * the default latency puts one register on each.
  *
  * @param rm      Some(mode) fixes the mode at elaboration; None adds an `rm` input
  * @param latency cycles from `in` to `out`
  */
class FpAdd(
    val fmt: FloatFormat,
    val rm: Option[RoundingMode],
    val latency: Int = FpAdd.defaultLatency,
    val subtract: Boolean = false
) extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, rm.isEmpty), UInt(fmt.width.W)))
  override def desiredName: String = FpUnitIO.name(if (subtract) "FpSub" else "FpAdd", fmt, rm, latency)

  private val pipe = new FpPipeline(latency, FpAdd.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpAdd.front(fmt, io.in.bits, subtract, stages))
  private val rounded = FpAddNorm(fmt, mid, Seq(FpUnitIO.roundingMode(rm, mid.rm)), stages).head
  io.out := pipe.cut(stages.valid, rounded)
  pipe.done()
}

/** [[FpAdd]] (or its subtractor) rounded both down (RDN) and up (RUP) from
  * one exact sum: one front and normaliser, two final roundings
  * (FpRound.finish). Each result is bit for bit the single-mode unit's
  * (an exact zero's sign included); same cuts and latency.
  */
class FpAddDnUp(val fmt: FloatFormat, val latency: Int = FpAdd.defaultLatency, val subtract: Boolean = false)
    extends Module {
  val io = IO(new FpUnitIO(new FpBinaryIn(fmt, false), new FpDnUp(fmt)))
  override def desiredName: String = s"${if (subtract) "FpSub" else "FpAdd"}DnUp_${fmt.name}_l$latency"

  private val modes = Seq(RoundingMode.RDN, RoundingMode.RUP).map(_.code.U(RoundingMode.width.W))
  private val pipe = new FpPipeline(latency, FpAdd.cuts(fmt))
  private val stages = new FpStages(pipe, io.in.valid)
  private val mid = stages(FpAdd.front(fmt, io.in.bits, subtract, stages))
  private val rounded = FpAddNorm(fmt, mid, modes, stages)
  io.out := pipe.cut(stages.valid, FpDnUp(fmt, rounded))
  pipe.done()
}

/** The adder front's state between its cuts. */
class FpAddFront(fmt: FloatFormat, dynamicRm: Boolean) extends Bundle {
  private val p = fmt.precision
  val big = new FpUnpacked(fmt)
  val smallSig = UInt(p.W)

  /** The larger operand's exponent field, 1 for a subnormal (the biased exponent of its hidden bit's place). */
  val bigExp = UInt(fmt.expBits.W)

  /** big.exp - small.exp: never negative (the swap) and at most 2^expBits - 2. */
  val dist = UInt((fmt.expBits + 1).W)
  val effSub = Bool()
  val isNaN = Bool()
  val isInf = Bool()
  val infSign = Bool()

  /** The alignment's multiplier ([[FpAlign]]) and its product's partials. */
  val shift = UInt(FpAlign.width(fmt).W)
  val dsp = new DspPartials(p + 1, FpAlign.width(fmt) + 1)
  val smallAligned = UInt((p + FpAdd.extra).W)
  val sticky = Bool()
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}

object FpAdd {

  /** Guard, round and sticky positions below the aligned LSB. Two would do
    * (FpRaw needs precision+1 bits when sticky; an effective subtraction with
    * d > extra loses at most one leading bit); three keeps a margin.
    */
  val extra: Int = 3

  /** The front: swap, align, add (its cuts of `stages`), up to the
    * normaliser's input.
    */
  def front(
      fmt: FloatFormat,
      in: FpBinaryIn,
      subtract: Boolean,
      stages: FpStages
  ): FpAddMid = {
    val p = fmt.precision
    val extra = FpAdd.extra
    val sw = p + extra

    val ua = FpUnpack(fmt, in.a)
    val ub0 = FpUnpack(fmt, in.b)
    val ub = WireInit(ub0)
    if (subtract) ub.sign := !ub0.sign // exact; NaN signs do not matter (canonical NaN out)

    val dynamicRm = in.rm.isDefined

    // Cut 1: swap by exponent. Both operands' LSB exponents carry the same
    // offset from their (subnormal-adjusted) fields, so fields are compared and
    // subtracted directly, both ways at once: no chain waits on another.
    val f0 = Wire(new FpAddFront(fmt, dynamicRm))
    f0 := DontCare
    f0.rm.foreach(_ := in.rm.get)
    // |a| >= |b|, compared as the magnitudes' bit patterns (IEEE magnitudes order as integers, subnormals
    // included), so the exponents are in order and, when they are equal, the significands too: a
    // difference is never negative, and the add stage needs no second chain for its negation nor a select
    // behind its carry chain (docs/fmax.md). NaNs compare arbitrarily; they leave as the canonical NaN.
    val aBig = in.a(fmt.width - 2, 0) >= in.b(fmt.width - 2, 0)
    val big = Mux(aBig, ua, ub)
    f0.big := big
    f0.smallSig := Mux(aBig, ub.sig, ua.sig)
    // dist = big.exp - small.exp >= 0, from the raw fields: a subnormal's field 0 stands for 1, so when only
    // the smaller operand is subnormal the field difference is one too big. Both candidates are chains on
    // the raw fields, picked after them (with the subnormal fix in front of each chain, 5.05 ns).
    val (ea, eb) = (in.a(fmt.width - 2, fmt.manBits), in.b(fmt.width - 2, fmt.manBits))
    val (eaZero, ebZero) = (ea === 0.U, eb === 0.U)
    // max(field, 1): set the low bit of a zero field.
    f0.bigExp := Mux(aBig, ea | eaZero.asUInt, eb | ebZero.asUInt)
    def less1(x: UInt, y: UInt): UInt = (x +& ~y)(fmt.expBits - 1, 0) // x - y - 1 when x > y
    f0.dist := Mux(
      aBig,
      Mux(ebZero && !eaZero, less1(ea, eb), ea -& eb),
      Mux(eaZero && !ebZero, less1(eb, ea), eb -& ea)
    )
    f0.effSub := ua.sign =/= ub.sign
    f0.isNaN := ua.isNaN || ub.isNaN || (ua.isInf && ub.isInf && f0.effSub)
    f0.isInf := ua.isInf || ub.isInf
    f0.infSign := Mux(ua.isInf, ua.sign, ub.sign)
    val f1 = stages(f0)

    // Cut 2: the alignment's one-hot multiplier (into the DSP48E1s' input registers); then the product's
    // cuts (DspMul), the operands carried unchanged through them.
    val f2 = Wire(new FpAddFront(fmt, dynamicRm))
    f2 := f1
    f2.shift := FpAlign.oneHot(fmt, f1.dist, (1 << fmt.expBits) - 2)
    val last = (1 to DspMul.cuts(FpAlign.width(fmt) + 1)).foldLeft(stages(f2)) { (prev, s) =>
      val n = Wire(new FpAddFront(fmt, dynamicRm))
      n := prev
      n.dsp := DspMul.step(s, prev.smallSig.zext, prev.shift.zext, prev.dsp)
      stages(n)
    }
    // Cut: the aligned significand and its sticky bit in registers. The sticky bit is an OR of the product's
    // low bits, and the add's carry chain takes it as its carry in: DSP48E1.P, the OR, the chain in one
    // cycle were 6.28 ns.
    val f3w = Wire(new FpAddFront(fmt, dynamicRm))
    f3w := last
    val product = DspMul.result(last.smallSig.zext, last.shift.zext, last.dsp).asUInt
    val (aligned, lost) = FpAlign.aligned(fmt, product)
    f3w.smallAligned := aligned
    f3w.sticky := lost
    val f3 = stages(f3w)

    // Cut 3: add or subtract, in one carry chain (the operand's inversion sits in the chain's LUTs). A true
    // difference is big - (smallAligned + d), d in (0,1) when sticky: = (big - smallAligned - 1) + (1 - d),
    // so subtract the sticky bit too. big >= smallAligned + sticky (the swap, and sticky needs the exponents
    // apart), so the difference is never negative: big + ~smallAligned + !sticky, the sticky's borrow as the
    // chain's carry in (an extra low bit: effSub + (effSub && !sticky) carries exactly that), and the carry
    // out of a difference (2^sw) dropped. A sum's extra low bits are 0 + 0 and carry nothing.
    //
    // Timing (docs/fmax.md): the carry chain feeds only the register.
    val sub = f3.effSub
    val bigExt = Cat(f3.big.sig, 0.U(extra.W))
    // The top bit: a difference always carries out of bit sw (big + 2^sw - 1 - smallAligned + !sticky >= 2^sw),
    // so an operand bit `sub` there makes the sum bit 0 for a difference and the carry for a sum, from the
    // chain itself (as an AND behind the chain it was the adder's longest path).
    val chain = Cat(0.U(1.W), bigExt, sub) + Cat(sub, f3.smallAligned ^ Fill(sw, sub), sub && !f3.sticky)

    // The exact-zero test and the result's sign wait for the normaliser's first stage ([[FpAddNorm]]), which
    // tests the registered sum for 0 beside its leading-zero count (as compares of the operands beside the
    // chain, 27 LUTs at FP32).
    val front = Wire(new FpAddMid(fmt, dynamicRm))
    front.rm.foreach(_ := f3.rm.get)
    front.isNaN := f3.isNaN
    front.isInf := f3.isInf
    front.infSign := f3.infSign
    front.bigSign := f3.big.sign
    front.effSub := f3.effSub
    front.sig := chain(sw + 1, 1)
    front.sticky := f3.sticky
    front.bigExp := f3.bigExp
    front
  }

  /** Swap, the alignment's multiplier and its product ([[DspMul]]), the aligned significand, add, the normaliser's and rounder's cut
    * points, the output. */
  def cuts(fmt: FloatFormat): Int = 4 + DspMul.cuts(FpAlign.width(fmt) + 1) + FpAddNorm.cuts + 1

  /** One register per cut point (docs/fmax.md). */
  def defaultLatency: Int = cuts(FloatFormat.FP32)
}
