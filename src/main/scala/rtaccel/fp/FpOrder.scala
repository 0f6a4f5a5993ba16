package rtaccel.fp

import chisel3._

/** Total order on non-NaN encodings of a format, without any arithmetic:
  * mapping sign-magnitude to an unsigned key in which -0 sits just below +0.
  * Used where two results only need ranking (closest hit), not IEEE compare.
  */
object FpOrder {
  def key(fmt: FloatFormat, x: UInt): UInt = {
    require(x.getWidth == fmt.width, s"FpOrder.key: expected ${fmt.width} bits for $fmt, got ${x.getWidth}")
    Mux(x(fmt.width - 1), ~x, x | (BigInt(1) << (fmt.width - 1)).U(fmt.width.W))
  }

  /** `key(a) <= key(b)`, from the signs and one compare of the magnitudes: the key's sign-dependent inversion
    * does not stand in front of the compare's carry chain. Negative encodings order by descending magnitude, and
    * every negative one below every positive one.
    */
  def keyLe(fmt: FloatFormat, a: UInt, b: UInt): Bool = {
    val w = fmt.width
    require(a.getWidth == w && b.getWidth == w, s"FpOrder.keyLe: expected $w bits for $fmt")
    val (sa, sb) = (a(w - 1), b(w - 1))
    val less = a(w - 2, 0) < b(w - 2, 0)
    val same = a(w - 2, 0) === b(w - 2, 0)
    Mux(sa =/= sb, sa, Mux(sa, !less, less || same))
  }

  /** Scala twin of `key`, for golden models. */
  def keyOf(fmt: FloatFormat, x: BigInt): BigInt = {
    val mask = (BigInt(1) << fmt.width) - 1
    if (x.testBit(fmt.width - 1)) ~x & mask else x | (BigInt(1) << (fmt.width - 1))
  }
}
