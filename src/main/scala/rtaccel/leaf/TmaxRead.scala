package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig
import rtaccel.system.HeadQueue
import rtaccel.traversal.TmaxUpdate

object TmaxRead {

  /** The tmax writes of LeafIntersect's exiting rays: each ray ID from `ids` (a head register) reads its best t
    * from `best` into a two-entry queue whose head (registers) is the write. Read as the exit leaves, by the exit
    * queue's head, the read's address ran into the best table's read-during-write compare (6.59 ns); read by the
    * ID queue's head straight into the write, the block RAM's clock-to-out ran through the RayBuffer's write
    * arbiter into its tmax memory (5.16 ns in the core's control, docs/fmax.md). From the table itself, with no
    * forward of the best's write in flight: an exit leaves two cycles or more after its last answer (its exit
    * register and the exit queue), and that answer's write lands the cycle after it (`leaf_tmax_landed`).
    */
  def apply(
      cfg: AccelConfig,
      ids: DecoupledIO[UInt],
      best: Mem[BestHit],
      bestWrite: Valid[BestWrite],
      bestNow: UInt => UInt
  ): DecoupledIO[TmaxUpdate] = {
    val out = Module(new HeadQueue(new TmaxUpdate(cfg)))
    out.io.enq.valid := ids.valid
    out.io.enq.bits.rayId := ids.bits
    out.io.enq.bits.tmax := best.read(ids.bits).t
    assert(
      !(ids.valid && bestWrite.valid && bestWrite.bits.id === ids.bits),
      "leaf_tmax_landed: a tmax is read while its ray's best hit is still being written"
    )
    ids.ready := out.io.enq.ready
    assert(
      !out.io.deq.valid || out.io.deq.bits.tmax === bestNow(out.io.deq.bits.rayId),
      "leaf_tmax_stands: a queued tmax write differs from its ray's best hit"
    )
    out.io.deq
  }

  /** Assertion only (synthesis drops it): no RayBuffer read (`reads`, valid and ray ID) of a ray whose tmax write
    * was owed from `owe` on and has not landed (`landed`) yet: `leaf_tmax_first`.
    */
  def checkFirst(n: Int, owe: (Bool, UInt), landed: (Bool, UInt), reads: Seq[(Bool, UInt)]): Unit = {
    val owedReg = RegInit(VecInit(Seq.fill(n)(false.B)))
    when(owe._1) { owedReg(owe._2) := true.B }
    when(landed._1) { owedReg(landed._2) := false.B }
    assert(
      reads.map { case (v, id) => !(v && owedReg(id)) }.reduce(_ && _),
      "leaf_tmax_first: a ray's RayBuffer read came before its tmax write landed"
    )
  }
}
