package rtaccel.leaf

import chisel3._
import chisel3.util._

/** A 1-of-n read of a per-ID table over two cycles: each group of `groupSize` entries selects its entry for `id`
  * (zero unless `id` is in the group) into a register, and the groups' entries are ORed a cycle later. A 1-of-128
  * read in one cycle maps to a chain of up to six LUT/MUXF7/MUXF8 levels (docs/fmax.md); this is a 16-to-1 select
  * and a compare, then an 8-input OR.
  */
object GroupedRead {

  /** `table(id)` as it stood a cycle ago, `id` being last cycle's. */
  def apply(table: Seq[UInt], id: UInt, groupSize: Int = 16): UInt =
    RegNext(VecInit(picks(table, id, groupSize))).reduce(_ | _)

  /** `table(id)` as it stood in the last cycle with `load` set, `id` being that cycle's. */
  def loaded(table: Seq[UInt], id: UInt, load: Bool, groupSize: Int = 16): UInt =
    RegEnable(VecInit(picks(table, id, groupSize)), load).reduce(_ | _)

  private def picks(table: Seq[UInt], id: UInt, groupSize: Int): Seq[UInt] = {
    val size = table.size.min(groupSize)
    val groups = (table.size + size - 1) / size
    val w = table.head.getWidth
    val low = id(log2Ceil(size).max(1) - 1, 0)
    (0 until groups).map { g =>
      val entries = (0 until size).map(j => table.lift(g * size + j).getOrElse(0.U(w.W)))
      val entry = if (size == 1) entries.head else VecInit(entries)(low)
      if (groups == 1) entry else Mux((id >> log2Ceil(size)) === g.U, entry, 0.U)
    }
  }
}
