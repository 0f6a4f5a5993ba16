package rtaccel.formal

import chisel3._
import rtaccel.RayIdFreeList

/** RayIdFreeList alone, every input free (any alloc.ready, any free, legal or
  * not): its own assertions (id_allocated_once, id_count) hold whatever
  * drives it, which `make formal-induction` proves for all time (PDR).
  */
class FormalFreeList(numIds: Int) extends Module {
  val io = IO(new Bundle {})
  override def desiredName = s"FormalTop_ids$numIds"
  private val ids = Module(new RayIdFreeList(numIds))
  ids.io.alloc.ready := FormalAnySeq(Bool())
  ids.io.free.valid := FormalAnySeq(Bool())
  ids.io.free.bits := FormalAnySeq(chiselTypeOf(ids.io.free.bits))
}
