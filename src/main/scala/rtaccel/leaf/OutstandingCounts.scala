package rtaccel.leaf

import chisel3._
import chisel3.util.Cat
import rtaccel.StepCount

/** LeafIntersect's per-ray-ID count of triangle requests not yet answered: +1
  * per request issued, -1 per answer reduced, both possibly in one cycle (the
  * cycle's `LeafWrites`).
  *
  * Beside each count, whether it is 0, 1, 2 or 3 (`flags`, bit k set when the
  * count is k, registers kept as the count moves, [[StepCount]]): the reduce
  * stage's read-ahead ([[LeafReadAhead]]) reads the flag its case needs, where a
  * select of the n counts and a compare after it was the unit's longest path, 12
  * cells of Yosys's mapping (docs/fmax.md).
  */
class OutstandingCounts(n: Int, bits: Int, w: LeafWrites) {
  private val steps = (0 until n).map { i =>
    val s = new StepCount(s"out$i", bits, 0 until 4)
    // Each count moves by at most one a cycle (a request and an answer of one ID in one cycle leave it), so
    // the new count and flags are a select among registers and their +-1 by the ID's two decodes: no adder or
    // compare sits behind the decodes (a sum of the events and a compare of the sum into the flags were the
    // unit's longest path, 8 LUT and a carry chain, docs/fmax.md).
    s.step(w.inc && w.incId === i.U, w.reduce && w.doneId === i.U)
    s
  }

  /** Each ID's count, its register. */
  val counts: Vec[UInt] = VecInit(steps.map(_.countReg))

  /** Each ID's flags, bit k the register of count = k. */
  val flags: Vec[UInt] = VecInit(steps.map(s => Cat((0 until 4).reverse.map(s.is))))

  assert(steps.map(_.flagsAgree).reduce(_ && _), "leaf_out_is: an outstanding count's flags disagree with it")
}
