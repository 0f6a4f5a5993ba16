package rtaccel

import chisel3._

/** The number of items a unit holds, counted from the handshakes that bring items in (`enters`) and take them
  * out (`leaves`). It reads exactly what a register updated by every handshake would hold: the items that
  * entered before this cycle, less those that left before it. The handshakes are registered before they are
  * added, so no valid/ready chain reaches the count's carry chain in its own cycle: the count is `countReg`
  * (the count as of the cycle before last) plus last cycle's registered handshakes, and `countReg` loads it. Where the count
  * was the unit's longest path, the chains into it were a ready's logic, a 1-of-n table read or an arbiter
  * (docs/fmax.md); this leaves one short add behind registers. Its registers live in the calling module, as
  * [[PerfCounter]]'s do, so the per-unit Fmax estimate sees them as the unit's own.
  */
object HeldCount {

  /** The count, `width` bits (wrapping as a `width`-bit register would), 0 at reset. */
  def apply(enters: Seq[Bool], leaves: Seq[Bool], width: Int): UInt = {
    require(enters.nonEmpty && leaves.nonEmpty, "HeldCount: needs at least one entry and one exit handshake")
    val enteredReg = RegNext(VecInit(enters), VecInit.fill(enters.size)(false.B))
    val leftReg = RegNext(VecInit(leaves), VecInit.fill(leaves.size)(false.B))
    val countReg = RegInit(0.U(width.W))
    val added = enteredReg.foldLeft(countReg)(_ + _.asUInt)
    val count = leftReg.foldLeft(added)(_ - _.asUInt)
    countReg := count
    count
  }
}
