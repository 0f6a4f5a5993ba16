package rtaccel.system

import chisel3._
import chisel3.util._

/** The lowest set bit of a vector as a binary tree: (any bit set, its index).
  * `PriorityEncoder` is a chain of muxes as long as the vector (over 63 slots a
  * 28-cell LUT/MUXF7/MUXF8 path, docs/fmax.md); here each level halves the
  * vector, so the depth grows with log2 of the width.
  */
object FirstSet {
  def apply(bits: UInt): (Bool, UInt) = {
    val w = bits.getWidth
    require(w >= 1, "FirstSet: empty vector")
    if (w == 1) (bits(0), 0.U(1.W))
    else tree((0 until (1 << log2Ceil(w))).map(i => if (i < w) bits(i) else false.B))
  }

  private def tree(bits: Seq[Bool]): (Bool, UInt) =
    if (bits.size == 2) (bits(0) || bits(1), !bits(0))
    else {
      val (lo, hi) = bits.splitAt(bits.size / 2)
      val (loAny, loIdx) = tree(lo)
      val (hiAny, hiIdx) = tree(hi)
      // Low half first: the same slot PriorityEncoder would pick.
      (loAny || hiAny, Cat(!loAny, Mux(loAny, loIdx, hiIdx)))
    }
}
