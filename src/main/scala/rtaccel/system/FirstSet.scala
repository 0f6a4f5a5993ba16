package rtaccel.system

import chisel3._
import chisel3.util._

import rtaccel.fp.FpUnpack

/** The lowest set bit of a vector as a binary tree: (any bit set, its index).
  * `PriorityEncoder` is a chain of muxes as long as the vector (over 63 slots a
  * 28-cell LUT/MUXF7/MUXF8 path, docs/fmax.md). The lowest set bit's index is
  * the leading-zero count of the reversed vector, and the rounder's
  * leading-zero count is already a tree whose depth grows with log2 of the
  * width, so this reuses it.
  */
object FirstSet {
  def apply(bits: UInt): (Bool, UInt) = {
    val w = bits.getWidth
    require(w >= 1, "FirstSet: empty vector")
    if (w == 1) (bits(0), 0.U(1.W))
    else (bits.orR, FpUnpack.leadingZeros(Reverse(bits)))
  }
}
