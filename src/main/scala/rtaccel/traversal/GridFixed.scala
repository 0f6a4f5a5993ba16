package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.fp.{FloatFormat, FpUnpack}

/** Widths of the grid box test (docs/kernels.md, "Box tests in the node's grid").
  *
  * @param qBits    bits of a child plane offset (8 in the 4q/8q layouts)
  * @param fracBits the node's distance unit u is 2^-fracBits .. 2^-(fracBits+1) of its smallest
  *                 grid step in t: how finely a child's slab ends are kept
  * @param width    signed width of a relative distance in units of u; it must hold qMax steps of
  *                 the smallest axis, qMax 2^(fracBits+1), so width >= qBits + fracBits + 3
  * @param cFracBits fraction bits of the ray's grid coordinate at t0
  */
final case class GridParams(qBits: Int = 8, fracBits: Int = 3, width: Int = 14, cFracBits: Int = 4) {
  require(qBits >= 1 && qBits <= 8, s"GridParams: qBits must be in 1..8, got $qBits")
  require(fracBits >= 0, s"GridParams: fracBits must be >= 0, got $fracBits")
  require(width >= qBits + fracBits + 3, s"GridParams: width $width < qBits + fracBits + 3 = ${qBits + fracBits + 3}")
  val qMax: Int = (1 << qBits) - 1

  /** The window of relative distances: anything outside is clamped to it (a monotone map). */
  val bot: BigInt = -(BigInt(1) << (width - 1))
  val top: BigInt = (BigInt(1) << (width - 1)) - 1

  /** A step in units of u, unsigned; one at the window's size or more ends every interval past it. */
  val stepBits: Int = width - 1
  val stepMax: BigInt = (BigInt(1) << stepBits) - 1

  /** A flat axis' grid coordinate, clamped to -1..qMax+1 (enough to decide q' <= g and g <= q'). */
  val gLo: BigInt = -1
  val gHi: BigInt = qMax + 1
  val gBits: Int = qBits + 2

  /** The ray's grid coordinate at t0 in units of 2^-cFracBits, kept within -2..qMax+2 cells (flags beyond). */
  val cLo: BigInt = -(BigInt(2) << cFracBits)
  val cHi: BigInt = BigInt(qMax + 2) << cFracBits
  val cBits: Int = GridFixed.widthOf(cLo, cHi)

  /** q' - c in units of 2^-cFracBits. */
  val dBits: Int = GridFixed.widthOf(-cHi, (BigInt(qMax) << cFracBits) - cLo)
  def name: String = s"q${qBits}f${fracBits}w${width}c$cFracBits"
}

/** A float scaled by 2^k, rounded to an integer (floor or ceil) and clamped
  * to [lo, hi]; `below`/`above` say the unclamped value was outside. Infinities
  * are outside on their side; a NaN counts as outside on the rounding's own side
  * (below for floor, above for ceil). Software and hardware, bit for bit.
  */
object GridFixed {
  final case class Fixed(value: BigInt, below: Boolean, above: Boolean)

  def soft(fmt: FloatFormat, x: BigInt, k: Int, up: Boolean, lo: BigInt, hi: BigInt): Fixed = {
    def clamp(v: BigInt) = Fixed(v.max(lo).min(hi), v < lo, v > hi)
    if (fmt.isNaN(x)) { if (up) Fixed(hi, false, true) else Fixed(lo, true, false) }
    else if (fmt.isInfinite(x)) { if (fmt.sign(x)) Fixed(lo, true, false) else Fixed(hi, false, true) }
    else {
      val sig = fmt.significand(x)
      val sh = fmt.lsbExponent(x) + k
      val (trunc, rem) =
        if (sh >= 0) (sig << sh, false)
        else if (-sh > fmt.precision) (BigInt(0), sig != 0)
        else (sig >> -sh, (sig & ((BigInt(1) << -sh) - 1)) != 0)
      val r = BigInt(if (rem) 1 else 0)
      clamp(if (!fmt.sign(x)) (if (up) trunc + r else trunc) else (if (up) -trunc else -(trunc + r)))
    }
  }

  class FixedHw(w: Int) extends Bundle {
    val value = SInt(w.W)
    val below = Bool()
    val above = Bool()
  }

  /** Signed width that holds lo..hi. */
  def widthOf(lo: BigInt, hi: BigInt): Int = (lo.abs.max(hi.abs).bitLength + 1).max(2)

  /** [[hw]]'s shift `k` as the three thresholds it is compared with, each a
    * constant less k: computed ahead of `x` (a caller may register them), so
    * that in hw each compare waits on one sum of x's own fields, not on k too.
    * For E the exponent field (1 for a subnormal), lz and tz sig's leading
    * and trailing zeros, and m = w - 1:
    *   - `right` - E = m - 1 - sh, sh = E - bias - manBits + k the LSB's exponent scaled:
    *     the right shift that puts sig's bit -sh at bit 0 (no shift when E > `right`, all of sig shifted out
    *     when E < `rightLessMax`);
    *   - big: msb(sig) + sh >= m, msb = p - 1 - lz, is E - lz >= `big`;
    *   - a remainder (a 1 of sig below bit -sh) is tz + E < `rem`.
    */
  class Shift(w: Int) extends Bundle {
    val right = SInt(w.W)

    /** `right` less the largest useful shift (p + m - 1): E below it shifts every bit out. */
    val rightLessMax = SInt(w.W)
    val big = SInt(w.W)
    val rem = SInt(w.W)
  }

  /** The largest right shift that keeps a bit of the significand in an m-bit window: p + m - 1. */
  private def maxShift(fmt: FloatFormat, m: Int): Int = fmt.precision + m - 1

  def shift(fmt: FloatFormat, k: SInt, lo: BigInt, hi: BigInt): Shift = {
    val m = widthOf(lo, hi) - 1
    val off = fmt.bias + fmt.manBits
    val s = Wire(new Shift(k.getWidth.max(log2Ceil(off + m + fmt.precision + 1) + 1) + 2))
    s.right := (m - 1 + off).S -& k
    s.rightLessMax := (m - 1 + off - maxShift(fmt, m)).S -& k
    s.big := (m - fmt.precision + 1 + off).S -& k
    s.rem := off.S -& k
    s
  }

  /** The hardware of [[soft]]: `k` a runtime SInt. Combinational. */
  def hw(fmt: FloatFormat, x: UInt, k: SInt, up: Boolean, lo: BigInt, hi: BigInt): FixedHw =
    hw(fmt, x, shift(fmt, k, lo, hi), up, lo, hi)

  /** How the result leaves the magnitude, decided from `x` alone and carried through every stage. */
  class Side extends Bundle {

    /** The rounding bump away from zero (ceil of a positive value, floor of a negative one). */
    val bump = Bool()
    val sign = Bool()

    /** A NaN goes to the window's edge on the rounding's side. */
    val isNaN = Bool()
  }

  /** What [[decide]] hands to [[front]]: the significand, its right shift
    * clamped, and the decisions on it. With a register after each of
    * [[decide]] and [[front]] the conversion is three pipeline stages (the
    * exponent's compares, the shifter, the signed result and the clamp), each
    * short of the FP units' own stages.
    */
  class Decided(p: Int, aBits: Int) extends Bundle {
    val sig = UInt(p.W)
    val aC = UInt(aBits.W)
    val big = Bool()
    val side = new Side
  }

  /** What [[front]] hands to [[back]]. */
  class Front(m: Int) extends Bundle {

    /** The saturated magnitude: below 2^m, or 2^m for `big`. */
    val mag = UInt((m + 1).W)
    val side = new Side
  }

  /** [[soft]] with the shift prepared by [[shift]] (for the same window).
    *
    * Only magnitudes below 2^m, m = w - 1, need their bits: lo and hi lie
    * within +-(2^m - 1), so a magnitude of 2^m or more (`big`) clamps on its
    * side, rounding bump or not, and is carried as 2^m. Below that, the
    * integer part of sig 2^sh is the m bits of sig from -sh up: one right
    * shift of sig padded with m - 1 zeros, by m - 1 - sh (a left shift of sig
    * when sh > 0, which is not `big` only for a subnormal sig). `big` and the
    * remainder are compares beside the shifter ([[Shift]]). The signed result
    * is one adder (the magnitude, complemented when negative, plus a carry
    * in), and the window's compares read the magnitude beside it.
    * Combinational: [[examine]], [[sums]], [[decide]], [[front]], [[back]], then [[clamp]].
    */
  def hw(fmt: FloatFormat, x: UInt, s: Shift, up: Boolean, lo: BigInt, hi: BigInt): FixedHw =
    clamp(back(front(decide(fmt, sums(fmt, examine(fmt, x)), s, up, lo, hi), lo, hi), up, lo, hi), up, lo, hi)

  /** What [[examine]] hands to [[decide]]: `x`'s fields and its significand's leading and trailing zeros. */
  class Examined(fmt: FloatFormat) extends Bundle {
    val sig = UInt(fmt.precision.W)
    val expF = UInt(fmt.expBits.W)
    val lz = UInt(log2Ceil(fmt.precision + 1).W)
    val tz = UInt(log2Ceil(fmt.precision + 1).W)
    val sign = Bool()
  }

  /** `x`'s fields and the zero counts of its significand (two trees of LUTs and wide muxes): the part of
    * [[decide]] that waits on no threshold. GridNodeStage registers it, so that no stage holds a count and the
    * compares behind it.
    */
  def examine(fmt: FloatFormat, x: UInt): Examined = {
    val expF = x(fmt.width - 2, fmt.manBits)
    val sig = Cat(expF.orR, x(fmt.manBits - 1, 0))
    val ex = Wire(new Examined(fmt))
    ex.sig := sig
    ex.expF := expF
    ex.lz := FpUnpack.leadingZeros(sig) // sig = 0 is flagged apart
    ex.tz := FpUnpack.leadingZeros(Reverse(sig))
    ex.sign := x(fmt.width - 1)
    ex
  }

  /** What [[sums]] hands to [[decide]]: the exponent E and its sums with the zero counts, and `x`'s classes. */
  class Summed(fmt: FloatFormat) extends Bundle {
    private val eBits = fmt.expBits + 2
    val sig = UInt(fmt.precision.W)
    val e = SInt(eBits.W)

    /** E - lz (the MSB's exponent, offset) and E + tz (the lowest 1's). */
    val eLz = SInt(eBits.W)
    val eTz = SInt(eBits.W)
    val sign = Bool()
    val nonzero = Bool()
    val isSpecial = Bool()
    val isNaN = Bool()
  }

  /** The exponent E (1 for a subnormal) and its sums with [[examine]]'s zero counts, each an adder of its own: a
    * stage apart from [[decide]], so that each of decide's compares reads registers and a constant less `k`.
    */
  def sums(fmt: FloatFormat, ex: Examined): Summed = {
    val expF = ex.expF
    val e = Mux(expF.orR, expF, 1.U).zext
    val o = Wire(new Summed(fmt))
    o.sig := ex.sig
    o.e := e
    o.eLz := e -& ex.lz.zext
    o.eTz := e +& ex.tz.zext
    o.sign := ex.sign
    o.nonzero := ex.sig.orR
    o.isSpecial := expF.andR
    o.isNaN := expF.andR && ex.sig(fmt.manBits - 1, 0).orR
    o
  }

  /** The compares on the exponent of the `x` that [[sums]] read: its right shift into the window, `big`, and
    * whether it rounds away from zero. The shift's clamps compare E with the thresholds beside the subtraction.
    */
  def decide(fmt: FloatFormat, su: Summed, s: Shift, up: Boolean, lo: BigInt, hi: BigInt): Decided = {
    val w = widthOf(lo, hi)
    val m = w - 1
    require(lo.abs < (BigInt(1) << m) && hi.abs < (BigInt(1) << m), s"GridFixed: $lo..$hi in $w bits")
    val p = fmt.precision
    val (e, sign, nonzero) = (su.e, su.sign, su.nonzero)
    val big = nonzero && (su.isSpecial || su.eLz >= s.big) // an infinity is big too
    val rem = nonzero && (su.eTz < s.rem)
    // Right by a = m - 1 - sh = right - E; a < 0 (E > right) is big (or sig = 0, which shifts to 0 anyway),
    // a > aMax = p + m - 1 (E < rightLessMax) leaves 0.
    val a = s.right -& e
    val aMax = maxShift(fmt, m)
    val aBits = log2Ceil(aMax + 1)
    val d = Wire(new Decided(p, aBits))
    d.sig := su.sig
    d.aC := Mux(e > s.right, 0.U, Mux(e < s.rightLessMax, aMax.U, a.asUInt(aBits - 1, 0)))
    d.big := big
    d.side.bump := rem && (if (up) !sign else sign)
    d.side.sign := sign
    d.side.isNaN := su.isNaN
    d
  }

  /** The shift: the magnitude in the window's bits, saturated. */
  def front(d: Decided, lo: BigInt, hi: BigInt): Front = {
    val m = widthOf(lo, hi) - 1
    val low = (Cat(d.sig, 0.U((m - 1).W)) >> d.aC)(m - 1, 0)
    val f = Wire(new Front(m))
    f.mag := Mux(d.big, (BigInt(1) << m).U, low.pad(m + 1))
    f.side := d.side
    f
  }

  /** What [[back]] hands to [[clamp]]: the signed result's window bits, and its compares with the window's ends
    * for each sign and rounding bump (index 2 sign + bump), of which [[clamp]] picks one.
    */
  class Backed(w: Int) extends Bundle {
    val v = SInt(w.W)
    val belowBy = Vec(4, Bool())
    val aboveBy = Vec(4, Bool())
    val side = new Side
  }

  /** The signed result of a [[front]] (the same `up` and window) and the compares that place it in the window,
    * side by side, each on the magnitude and a constant: GridNodeStage registers them, so that neither the pick
    * among them nor the clamp's select is behind a compare.
    */
  def back(f: Front, up: Boolean, lo: BigInt, hi: BigInt): Backed = {
    val w = widthOf(lo, hi)
    val m = w - 1
    val (mag, bump, sign) = (f.mag, f.side.bump, f.side.sign)
    // -(mag + bump) = ~mag + !bump in m + 2 bits.
    val v = ((mag.pad(m + 2) ^ Fill(m + 2, sign)) + Mux(sign, !bump, bump)).asSInt
    // v < lo and v > hi from mag, per sign and bump: a positive v is mag + bump, a negative one -(mag + bump).
    def magLt(c: BigInt) = mag.zext < c.S
    def magGt(c: BigInt) = mag.zext > c.S
    val out = Wire(new Backed(w))
    out.v := v(w - 1, 0).asSInt
    out.belowBy := VecInit(magLt(lo), magLt(lo - 1), magGt(-lo), magGt(-lo - 1))
    out.aboveBy := VecInit(magGt(hi), magGt(hi - 1), magLt(-hi), magLt(-hi - 1))
    out.side := f.side
    out
  }

  /** A [[back]]'s result (the same `up` and window) clamped to the window lo..hi; a NaN goes to the edge on the
    * rounding's side.
    */
  def clamp(b: Backed, up: Boolean, lo: BigInt, hi: BigInt): FixedHw = {
    val w = widthOf(lo, hi)
    val pick = Cat(b.side.sign, b.side.bump)
    val below = Mux(b.side.isNaN, (!up).B, b.belowBy(pick))
    val above = Mux(b.side.isNaN, up.B, b.aboveBy(pick))
    val out = Wire(new FixedHw(w))
    out.below := below
    out.above := above
    out.value := Mux(below, lo.S(w.W), Mux(above, hi.S(w.W), b.v))
    out
  }
}
