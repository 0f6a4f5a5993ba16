package rtaccel.fp

import chisel3._

/** An unrounded result: special-case flags, or the exact value
  * `(-1)^sign * (sig + d) * 2^exp` where `d` is 0 without `sticky` and lies in
  * (0, 1) with it. The front half of every unit produces one; [[FpRound]]
  * turns it into a format encoding. With `sticky`, `sig` must have at least
  * `precision + 1` significant bits (the unknown part stays below the guard bit).
  */
class FpRaw(val sigWidth: Int, val expWidth: Int) extends Bundle {
  val isNaN = Bool()

  /** Infinity of sign `sign` (ignored if `isNaN`). */
  val isInf = Bool()

  /** Zero of sign `sign` (an exact zero result; `sig` is ignored). */
  val isZero = Bool()
  val sign = Bool()
  val sig = UInt(sigWidth.W)
  val exp = SInt(expWidth.W)
  val sticky = Bool()
}

/** An unrounded result on its way through the pipeline, with its rounding
  * mode when the mode is a runtime input.
  */
class FpRawStage(sigWidth: Int, expWidth: Int, dynamicRm: Boolean) extends Bundle {
  val raw = new FpRaw(sigWidth, expWidth)
  val rm = Option.when(dynamicRm)(UInt(RoundingMode.width.W))
}
