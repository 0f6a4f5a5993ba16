package rtaccel.leaf

import chisel3._

/** LeafIntersect's per-ray-ID count of triangle requests not yet answered: +1
  * per request issued, -1 per answer reduced, both possibly in one cycle (the
  * cycle's `LeafWrites`).
  *
  * Beside each count, whether it is 0, 1, 2 or 3 (`isReg`, bit k set when the
  * count is k, from the count's next value): the reduce stage's read-ahead
  * ([[LeafReadAhead]]) reads the flag its case needs, where a select of the n
  * counts and a compare after it was the unit's longest path, 12 cells of
  * Yosys's mapping (docs/fmax.md).
  */
class OutstandingCounts(n: Int, bits: Int, w: LeafWrites) {
  val countsReg: Vec[UInt] = RegInit(VecInit(Seq.fill(n)(0.U(bits.W))))
  val isReg: Vec[UInt] = RegInit(VecInit(Seq.fill(n)(1.U(4.W)))) // every count is 0 at reset

  private val next = (0 until n).map { i =>
    countsReg(i) + (w.inc && w.incId === i.U).asUInt - (w.reduce && w.doneId === i.U).asUInt
  }
  private def flags(count: UInt): UInt = VecInit((0 until 4).map(k => count === k.U)).asUInt
  countsReg := VecInit(next)
  isReg := VecInit(next.map(flags))
  assert(
    isReg.asUInt === VecInit(countsReg.map(flags)).asUInt,
    "leaf_out_is: an outstanding count's flags disagree with it"
  )
}
