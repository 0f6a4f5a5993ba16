package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.fp.FloatFormat

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

  /** The hardware of [[soft]]: `k` a runtime SInt. Combinational. */
  def hw(fmt: FloatFormat, x: UInt, k: SInt, up: Boolean, lo: BigInt, hi: BigInt): FixedHw = {
    val w = widthOf(lo, hi)
    val magBits = w // |value| < 2^magBits covers lo..hi with room for one more
    val p = fmt.precision
    val expF = x(fmt.width - 2, fmt.manBits)
    val frac = x(fmt.manBits - 1, 0)
    val sign = x(fmt.width - 1)
    val isSpecial = expF.andR
    val isNaN = isSpecial && frac.orR
    val sig = Cat(expF.orR, frac)
    val lsbExp = (Mux(expF.orR, expF, 1.U).zext - (fmt.bias + fmt.manBits).S)
    val sh = lsbExp +& k
    // Left: sh in 0..magBits (beyond, the magnitude is >= 2^magBits unless sig is 0).
    val left = sh >= 0.S
    val big = sig.orR && (sh > magBits.S || isSpecial)
    val lAmt = sh.asUInt(log2Ceil(magBits + 1) - 1, 0)
    val lVal = (sig << Mux(sh > magBits.S, magBits.U, lAmt))(p + magBits - 1, 0)
    // Right: by 1..p+1 (more gives 0 with a remainder iff sig != 0).
    val rAmtFull = (-sh).asUInt
    val rAmt = Mux((-sh) > (p + 1).S, (p + 1).U, rAmtFull(log2Ceil(p + 2) - 1, 0))
    val rVal = sig >> rAmt
    val rRem = (rVal << rAmt)(p, 0) =/= sig
    val trunc = Mux(left, lVal, rVal.pad(p + magBits))
    val rem = !left && rRem
    val mag = Mux(big, (BigInt(1) << magBits).U, trunc.pad(p + magBits + 1)) // saturated magnitude
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
