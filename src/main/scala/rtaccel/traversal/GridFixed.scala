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

  /** The hardware of [[soft]]: `k` a runtime SInt. Combinational.
    *
    * Only magnitudes below 2^m, m = w - 1, need their bits: lo and hi lie
    * within +-(2^m - 1), so a magnitude of 2^m or more (`big`) clamps on its
    * side, rounding bump or not, and is carried as 2^m. Below that, the
    * integer part of sig 2^sh is the m bits of sig from -sh up: one right
    * shift of sig padded with m - 1 zeros, by m - 1 - sh (a left shift of
    * sig when sh > 0, which is not `big` only for a subnormal sig). `big` is
    * msb(sig) + sh >= m from sig's leading zeros, and the remainder (bits of
    * sig below -sh) is its trailing zeros < -sh: both compares beside the
    * shifter, not shifts of their own.
    */
  def hw(fmt: FloatFormat, x: UInt, k: SInt, up: Boolean, lo: BigInt, hi: BigInt): FixedHw = {
    val w = widthOf(lo, hi)
    val m = w - 1
    require(lo.abs < (BigInt(1) << m) && hi.abs < (BigInt(1) << m), s"GridFixed: $lo..$hi in $w bits")
    val p = fmt.precision
    val expF = x(fmt.width - 2, fmt.manBits)
    val frac = x(fmt.manBits - 1, 0)
    val sign = x(fmt.width - 1)
    val isSpecial = expF.andR
    val isNaN = isSpecial && frac.orR
    val sig = Cat(expF.orR, frac)
    val nonzero = sig.orR
    val lsbExp = (Mux(expF.orR, expF, 1.U).zext - (fmt.bias + fmt.manBits).S)
    val sh = lsbExp +& k
    val lz = FpUnpack.leadingZeros(sig) // sig = 0 is flagged apart
    val tz = FpUnpack.leadingZeros(Reverse(sig))
    // msb(sig) + sh >= m with msb(sig) = p - 1 - lz; an infinity is big too.
    val big = nonzero && (isSpecial || sh - lz.zext >= (m - p + 1).S)
    // Right by a = m - 1 - sh; a < 0 is big (or sig = 0, which shifts to 0 anyway), a > p + m - 2 leaves 0.
    val a = (m - 1).S - sh
    val aMax = p + m - 1
    val aBits = log2Ceil(aMax + 1)
    val aC = Mux(a < 0.S, 0.U, Mux(a > aMax.S, aMax.U, a.asUInt(aBits - 1, 0)))
    val low = (Cat(sig, 0.U((m - 1).W)) >> aC)(m - 1, 0)
    // Some bit of sig below -sh: tz < -sh.
    val rem = nonzero && (tz.zext + sh < 0.S)
    val mag = Mux(big, (BigInt(1) << m).U, low.pad(m + 1)) // saturated magnitude
    val bumped = mag +& Mux(rem, 1.U, 0.U)
    val posV = (if (up) bumped else mag).zext
    val negV = -(if (up) mag else bumped).zext
    val v = Mux(sign, negV, posV)
    val out = Wire(new FixedHw(w))
    val below = Mux(isNaN, (!up).B, v < lo.S)
    val above = Mux(isNaN, up.B, v > hi.S)
    out.below := below
    out.above := above
    out.value := Mux(below, lo.S(w.W), Mux(above, hi.S(w.W), v(w - 1, 0).asSInt))
    out
  }
}
