package rtaccel.leaf

import chisel3._
import chisel3.util.Cat

/** LeafIntersect's per-ray-ID count of triangle requests not yet answered: +1
  * per request issued, -1 per answer reduced, both possibly in one cycle (the
  * cycle's `LeafWrites`).
  *
  * Beside each count, whether it is 0, 1, 2 or 3 (`isReg`, bit k set when the
  * count is k, kept beside the count as it moves): the reduce stage's read-ahead
  * ([[LeafReadAhead]]) reads the flag its case needs, where a select of the n
  * counts and a compare after it was the unit's longest path, 12 cells of
  * Yosys's mapping (docs/fmax.md).
  */
class OutstandingCounts(n: Int, bits: Int, w: LeafWrites) {
  val countsReg: Vec[UInt] = RegInit(VecInit(Seq.fill(n)(0.U(bits.W))))
  val isReg: Vec[UInt] = RegInit(VecInit(Seq.fill(n)(1.U(4.W)))) // every count is 0 at reset

  // Each count moves by at most one a cycle: +1 (a request alone), -1 (an answer alone) or not at all. The new
  // count and flags are a select among registers and their +-1 by the ID's two decodes, so no adder or compare
  // sits behind the decodes (a sum of the events and a compare of the sum into the flags were the unit's longest
  // path, 8 LUT and a carry chain, docs/fmax.md).
  for (i <- 0 until n) {
    val up = w.inc && w.incId === i.U
    val down = w.reduce && w.doneId === i.U
    val plus = up && !down
    val minus = down && !up
    val count = countsReg(i)
    countsReg(i) := Mux(plus, count + 1.U, Mux(minus, count - 1.U, count))
    // Flag k of count + 1 is flag k - 1 of count; flag k of count - 1 is flag k + 1, and flag 3 is count = 4.
    val flagsUp = (isReg(i) << 1)(3, 0)
    val flagsDown = Cat((count === 4.U).asUInt, isReg(i)(3, 1))
    isReg(i) := Mux(plus, flagsUp, Mux(minus, flagsDown, isReg(i)))
  }
  private def flags(count: UInt): UInt = VecInit((0 until 4).map(k => count === k.U)).asUInt
  assert(
    isReg.asUInt === VecInit(countsReg.map(flags)).asUInt,
    "leaf_out_is: an outstanding count's flags disagree with it"
  )
}
