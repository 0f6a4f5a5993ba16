package rtaccel.fp

import chisel3._
import chisel3.util._

/** The hardware rounder shared by every arithmetic unit: normalise (leading
  * zero count and shift, clamped at the subnormal boundary), round once in the
  * mode, encode, and substitute special values. It computes exactly what
  * [[FpRounding.round]] computes in the model.
  *
  * `minExp`, when the caller knows it, is the smallest `raw.exp` that can
  * occur. A value on the subnormal grid sits `2 - exp - w - bias` places to
  * the right of "MSB at the top" (independent of the leading-zero count), so
  * if that is never positive one left shift, stopped at the grid, normalises
  * every result and the right shifter is left out (the adder and same-range
  * conversions). Otherwise one shift of `sig` in a frame p + 2 bits wider
  * does both the normalisation and the right shift onto the grid.
  *
  * Pipelining: a unit that passes its [[FpStages]] gets [[FpRound.cuts]] cut
  * points inside the rounder (after the leading-zero count, after the
  * shift amount (general path only), after the shift, after the rounding
  * decision); without, the rounder is
  * combinational. The exponent arithmetic is arranged so that no carry chain
  * waits on another inside a stage (the tiny test and the shifts read the
  * leading-zero count and exponent sums computed beside it); every value is
  * the same integer the straightforward formula gives.
  */
object FpRound {
  private def fastPath(fmt: FloatFormat, w: Int, pad: Int, minExp: Option[Int]): Boolean =
    minExp.map(e => 2 - (e - pad) - w - fmt.bias).exists(_ <= 0)
  private def pad(fmt: FloatFormat, sigWidth: Int): Int = (fmt.precision + 2 - sigWidth).max(0)

  /** Cut points inside the rounder for a raw value of `sigWidth` bits. */
  def cuts(fmt: FloatFormat, sigWidth: Int, minExp: Option[Int] = None): Int = {
    val pd = pad(fmt, sigWidth)
    if (fastPath(fmt, sigWidth + pd, pd, minExp)) 3 else 4
  }

  /** Everything the stages pass on; fields not yet computed are DontCare. Its first fields look like
    * [[FpRaw]]'s but are not the same values: `zero` also covers a significand that cancelled to 0, `sig`
    * carries the guard pad, and the exponent is replaced from stage 1 on by `eTop`/`eTopM1`, so an
    * FpRaw field would carry a dead exponent through every cut.
    */
  private[fp] class State(w: Int, p: Int, ew: Int, lzw: Int, dynamicRm: Boolean, modes: Int, tzWidth: Int = 0)
      extends Bundle {
    val isNaN = Bool()
    val isInf = Bool()
    val zero = Bool()

    /** Per mode (they differ only for an exact zero's sign, e.g. x - x in RDN). */
    val sign = Vec(modes, Bool())
    val sticky = Bool()
    val sig = UInt(w.W)
    val lz = UInt(lzw.W)

    /** Biased exponent of the MSB position, one less and one more. */
    val eTop = SInt(ew.W)
    val eTopM1 = SInt(ew.W)
    val eTopP1 = SInt(ew.W)

    /** eTopM1 + p + 2: the shift of the window's frame (w + p + 2 bits) that stops at the subnormal grid. */
    val eShiftOut = SInt(ew.W)
    val biasedExp = SInt(ew.W)
    val biasedExpP1 = SInt(ew.W)
    val tiny = Bool()

    /** The one shift of the general path, left in a frame of w + p + 2 bits (see FpRound.inModes). */
    val shift = UInt(log2Ceil(w + p + 2).W)

    /** w less the trailing zeros of `sig`, when the caller gives them ([[FpRound.inModes]]). */
    val tzRest = Option.when(tzWidth > 0)(UInt(tzWidth.W))

    /** The kept p bits, guard and round (`window`); any 1 below them (`tail`). */
    val window = UInt((p + 2).W)
    val tail = Bool()
    val up = Vec(modes, Bool())

    /** The kept bits below the top one are all ones: rounding up carries into the top bit. */
    val lowOnes = Bool()
    val expNormal = SInt(ew.W)
    val expInc = SInt(ew.W)
    val ovSame = Bool()
    val ovInc = Bool()
    val overflowToInf = Vec(modes, Bool())
    val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
  }

  /** `raw` rounded in `rm`. */
  def apply(
      fmt: FloatFormat,
      raw: FpRaw,
      rm: UInt,
      minExp: Option[Int] = None,
      stages: Option[FpStages] = None,
      trailingZeros: Option[UInt] = None
  ): UInt = inModes(fmt, raw, Seq((rm, raw.sign)), minExp, stages, trailingZeros).head

  /** `raw` rounded in several modes at once, each `(mode, sign)` with the
    * result's sign in that mode (`raw.sign` is not read): one normaliser,
    * and per mode only the rounding decision and the final increment and
    * encoding. Each result is the bits [[apply]] gives for that mode and sign.
    * A runtime mode (not a literal) is allowed only alone.
    *
    * `trailingZeros`, when the caller has it (the multiplier, from its operands'), is the number of trailing
    * zeros of a nonzero `raw.sig`; the general path then forms its tail bit by one compare of the shift
    * with it instead of masking `sig` (see below).
    */
  def inModes(
      fmt: FloatFormat,
      raw: FpRaw,
      modes: Seq[(UInt, Bool)],
      minExp: Option[Int],
      stages: Option[FpStages],
      trailingZeros: Option[UInt] = None
  ): Seq[UInt] = {
    val nModes = modes.size
    val rm = modes.head._1
    val p = fmt.precision
    // At least a guard bit and one more below the kept bits.
    val pd = pad(fmt, raw.sigWidth)
    val w = raw.sigWidth + pd
    // Every exponent here is raw.exp, less the pad (< w), plus a constant of at most w + bias + p, less at
    // most lz < w: with |raw.exp| <= 2^(E-1) (E its width) and X = 3w + bias + p + 2, ew signed bits hold
    // them all when 2^(ew-1) > 2^(E-1) + X, which ew = max(E, log2Ceil(X + 1) + 1) + 1 gives. (A wider
    // margin made every exponent chain and compare 19 bits in the FP32 multiplier; these are 12.)
    val ew = raw.expWidth.max(FpUnpack.expWidth(fmt)).max(log2Ceil(3 * w + fmt.bias + p + 3) + 1) + 1
    val lzw = log2Ceil(w)
    val dynamicRm = !rm.isLit
    require(nModes >= 1 && (!dynamicRm || nModes == 1), s"FpRound: $nModes modes, a runtime one among them")
    def cut(s: State): State = stages.fold(s)(_(s))
    val tzw = if (trailingZeros.isDefined) log2Ceil(w + 1) else 0
    def next(s: State): State = { val n = Wire(new State(w, p, ew, lzw, dynamicRm, nModes, tzw)); n := s; n }

    // Stage 1: leading zeros, and the exponent sums the next stage compares them with.
    val s0 = Wire(new State(w, p, ew, lzw, dynamicRm, nModes, tzw))
    s0 := DontCare
    s0.rm.foreach(_ := rm)
    val sig = if (pd > 0) Cat(raw.sig, 0.U(pd.W)) else raw.sig
    val exp = raw.exp.pad(ew) - pd.S(ew.W)
    s0.isNaN := raw.isNaN
    s0.isInf := raw.isInf
    s0.zero := raw.isZero || sig === 0.U
    s0.sign := VecInit(modes.map(_._2))
    s0.sticky := raw.sticky
    s0.sig := sig
    s0.lz := FpUnpack.leadingZeros(sig) // zero is flagged apart
    // Biased exponent of the leading one is eTop - lz.
    s0.eTop := exp + (w - 1 + fmt.bias).S(ew.W)
    s0.eTopM1 := exp + (w - 2 + fmt.bias).S(ew.W)
    s0.eTopP1 := exp + (w + fmt.bias).S(ew.W)
    val fast = fastPath(fmt, w, pd, minExp)
    require(trailingZeros.isEmpty || !fast, "FpRound: trailing zeros are for the general path")
    // w - tz(sig) in [1, w] (sig nonzero, its pad's zeros counted), beside the leading-zero count.
    s0.tzRest.foreach(_ := (w - pd).U - trailingZeros.get)
    if (!fast) s0.eShiftOut := exp + (w - 2 + fmt.bias + p + 2).S(ew.W)
    val s1 = cut(s0)

    // Stage 2: tiny (eTop - lz < 1, i.e. lz > eTop - 1), the extra right shift onto the
    // subnormal grid (1 - biasedExp = lz - (eTop - 1)), and the normalising shift.
    val s2 = next(s1)
    val lzS = s1.lz.zext.pad(ew)
    s2.biasedExp := s1.eTop - lzS
    s2.biasedExpP1 := s1.eTopP1 - lzS // the rounding carry's exponent, beside it: no chain on a chain next stage
    s2.tiny := s1.eTopM1 < lzS
    def below(amount: UInt): Bool = FpRound.below(s1.sig, p, amount)
    val s3 =
      if (fast) {
        // Never below the subnormal grid: one left shift, stopped at the grid, does both.
        // lz - subShift is eTop - 1 when tiny, lz otherwise (the same bits mod 2^lzw). Both shifts are
        // made and `tiny` picks one, so the compare runs beside the shifters (as the shift amount's select,
        // the compare, the select and the shifter were the adder's longest path, 5.26 ns).
        def window(amount: UInt): UInt = (s1.sig << amount)(w - 1, w - p - 2)
        val atGrid = s1.eTopM1.asUInt(lzw - 1, 0)
        s2.window := Mux(s2.tiny, window(atGrid), window(s1.lz))
        s2.tail := Mux(s2.tiny, below(atGrid), below(s1.lz)) || s1.sticky
        cut(s2)
      } else {
        // One shift does both the normalising left shift and the right shift onto the subnormal grid: the
        // window is the top p + 2 bits of sig 2^amt with amt = min(lz, eTop - 1) (negative: a right shift),
        // taken from Y = sig under k = p + 2 zero bits (a frame of w + k bits) shifted left by s = amt + k.
        // Not tiny, s = lz + k: the normalised window. Tiny, s = eTop - 1 + k = eShiftOut, clamped at 0: for
        // amt <= -k the window is 0 and every bit of sig is in the tail, as at s = 0. Stage 2 forms s beside
        // the tiny compare, stage 3 shifts by the registered s. (A normalising shift of all w bits and then a
        // right shift of the window took two shifters: half the FP32 multiplier's LUTs, 243 of 450.)
        val k = p + 2
        val sw = s2.shift.getWidth
        val atGrid = Mux(s1.eShiftOut < 0.S, 0.U, s1.eShiftOut.asUInt(sw - 1, 0))
        s2.shift := Mux(s2.tiny, atGrid, s1.lz +& k.U)
        val s2b = cut(s2)
        val s3 = next(s2b)
        // The bits of Y << s below the window (index < w) are sig's bits j with j + s < w: one of them is
        // 1 exactly when the lowest 1 of sig, at j = tz(sig), is one, i.e. s < w - tz(sig). With the
        // caller's count that is one compare of two registers (the mask and OR of sig's bits took 52 of the
        // FP32 multiplier's LUTs, and were the longest path of a box lane, 5.00 ns); a zero sig is flagged
        // apart.
        s3.window := FpUnpack.shiftLeftMsbFirst(Cat(0.U(k.W), s2b.sig), s2b.shift)(w + k - 1, w)
        val lost = s2b.tzRest.fold(FpRound.below(Cat(0.U(k.W), s2b.sig), p, s2b.shift))(s2b.shift < _)
        s3.tail := lost || s2b.sticky
        cut(s3)
      }

    finish(fmt, s3, modes.map(_._1), stages)
  }

  /** Whether `sig << amount` has a 1 below the window of p + 2 bits at its top (its low w - p - 2 bits),
    * formed beside the shifter: those are the bits of `sig` below w - p - 2 - amount, so `sig` masked by a
    * decode of the amount (bit j kept when j + amount < w - p - 2). As an OR of the shifter's output it was
    * the multiplier's longest path, 8 cells (2 LUT, 6 MUXF), 5.36 ns.
    */
  private[fp] def below(sig: UInt, p: Int, amount: UInt): Bool = {
    val w = sig.getWidth
    if (w > p + 2) (sig(w - p - 3, 0) & (Fill(w - p - 2, 1.U(1.W)) >> amount)).orR else false.B
  }

  /** The rounder's last two stages, shared with [[FpAddNorm]]: from the normalised `s3` (its `window`,
    * `tail`, `sign`, `tiny`, `biasedExp`, `biasedExpP1`, the flags and the runtime mode, if any) the
    * rounding decision and both candidate exponents with their overflow tests (one cut of `stages`), then
    * the increment, the encoding and the special values, per mode (`modes`, literal or the one runtime mode).
    */
  private[fp] def finish(fmt: FloatFormat, s3: State, modes: Seq[UInt], stages: Option[FpStages]): Seq[UInt] = {
    val p = fmt.precision
    val nModes = modes.size
    val ew = s3.biasedExp.getWidth
    def cut(s: State): State = stages.fold(s)(_(s))
    def rmOf(s: State, j: Int): UInt = s.rm.getOrElse(modes(j))
    val s4 = Wire(chiselTypeOf(s3))
    s4 := s3
    // Stage 3: the rounding decision, and both candidate exponents with their overflow tests.
    val kept0 = s3.window(p + 1, 2)
    val guard = s3.window(1)
    val rest = s3.window(0) || s3.tail
    val inexact = guard || rest
    for (j <- 0 until nModes) {
      val rm3 = rmOf(s3, j)
      val sign = s3.sign(j)
      s4.up(j) := MuxLookup(rm3, false.B)(Seq(
        RoundingMode.RNE.code.U -> (guard && (rest || kept0(0))),
        RoundingMode.RTZ.code.U -> false.B,
        RoundingMode.RDN.code.U -> (sign && inexact),
        RoundingMode.RUP.code.U -> (!sign && inexact)
      ))
      // Overflow goes to infinity only when the mode rounds away from zero on this side.
      s4.overflowToInf(j) := rm3 === RoundingMode.RNE.code.U ||
        (rm3 === RoundingMode.RUP.code.U && !sign) || (rm3 === RoundingMode.RDN.code.U && sign)
    }
    s4.lowOnes := kept0(p - 2, 0).andR
    // expInc is expNormal + 1 and each overflow test compares a registered value: the mux is the last step.
    s4.expNormal := Mux(s3.tiny, 1.S(ew.W), s3.biasedExp)
    s4.expInc := Mux(s3.tiny, 2.S(ew.W), s3.biasedExpP1)
    s4.ovSame := Mux(s3.tiny, (1 >= fmt.maxExpField).B, s3.biasedExp >= fmt.maxExpField.S)
    s4.ovInc := Mux(s3.tiny, (2 >= fmt.maxExpField).B, s3.biasedExpP1 >= fmt.maxExpField.S)
    val s5 = cut(s4)

    // Stage 4: round, encode, substitute special values (per mode). The increment's carries into the top
    // kept bit and out of it are known from `lowOnes` and the top bit, so the exponent, the overflow test and
    // the special-value select do not wait on the increment's carry chain, which feeds only the fraction bits
    // (docs/fmax.md). Each is the bit of `kept + up` it stands for.
    val kept = s5.window(p + 1, 2)
    (0 until nModes).map { j =>
      val rounded = kept +& s5.up(j)
      val intoTop = s5.up(j) && s5.lowOnes
      val carry = intoTop && kept(p - 1) // rounded(p): 1.11..1 rounded up to 10.00..0, the next binade
      val top = kept(p - 1) ^ intoTop // rounded(p - 1)
      val expOut = Mux(carry, s5.expInc, Mux(top, s5.expNormal, 0.S))
      val fracOut = rounded(p - 2, 0) // 0 when carry
      // expOut >= maxExpField, from the tests made beside each candidate (0 never overflows).
      val overflow = Mux(carry, s5.ovInc, top && s5.ovSame)
      val sign = s5.sign(j)
      val signBit = Cat(sign, 0.U((fmt.width - 1).W))
      MuxCase(
        Cat(sign, expOut(fmt.expBits - 1, 0), fracOut),
        Seq(
          s5.isNaN -> fmt.canonicalNaN.U(fmt.width.W),
          s5.isInf -> (signBit | fmt.infinity(false).U),
          s5.zero -> signBit,
          overflow -> (signBit | Mux(s5.overflowToInf(j), fmt.infinity(false).U, fmt.maxFinite(false).U))
        )
      )
    }
  }
}
