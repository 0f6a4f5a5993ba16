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

  /** Scala twin of `key`, for golden models. */
  def keyOf(fmt: FloatFormat, x: BigInt): BigInt = {
    val mask = (BigInt(1) << fmt.width) - 1
    if (x.testBit(fmt.width - 1)) ~x & mask else x | (BigInt(1) << (fmt.width - 1))
  }
}
