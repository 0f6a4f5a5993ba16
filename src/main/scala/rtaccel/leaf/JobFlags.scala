package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ErrorFlags}

/** A job's table entries, read as it enters LeafIntersect's job queue and waiting beside it. */
class JobFlags extends Bundle {
  val occ = Bool()
  val err = UInt(ErrorFlags.width.W)
  val hit = Bool()
}

object JobFlags {

  /** The entries of the job at the head of `jobs`, read as it entered.
    *
    * Read when the job is taken, from the job queue's head, the select was the
    * unit's longest path (6.07 ns, docs/fmax.md). So each job's entries are
    * read in two stages ([[GroupedRead]]) as it enters, and wait in a queue
    * beside it (enqueued a cycle after the job, passing straight through when
    * that queue is empty, so a job is never held back). A job's ray has no
    * request outstanding and no clear can come for it (a ray's clear comes
    * before its first job, in an earlier cycle), so its entries stand still
    * from its entry until it is taken (checked: `leaf_job_flags`).
    */
  def beside(cfg: AccelConfig, jobs: QueueIO[LeafJob], t: LeafTables): JobFlags = {
    val enteredId = jobs.enq.bits.token.rayId
    val entered = Wire(new JobFlags)
    entered.occ := GroupedRead(t.occluded.map(_.asUInt), enteredId).asBool
    entered.err := GroupedRead(t.errors, enteredId)
    entered.hit := GroupedRead(t.hasHit.map(_.asUInt), enteredId).asBool
    // As many entries as `jobs`, and never more in it than in `jobs`: it cannot overflow (checked all the same).
    val flags = Module(new Queue(new JobFlags, cfg.numRayIds, flow = true))
    flags.io.enq.valid := RegNext(jobs.enq.fire, false.B)
    flags.io.enq.bits := entered
    flags.io.deq.ready := jobs.deq.fire
    assert(!flags.io.enq.valid || flags.io.enq.ready, "no_overflow_leaf_flags: a job's flags found no room")
    assert(!jobs.deq.valid || flags.io.deq.valid, "leaf_flags_aligned: a job's flags are not beside it")
    val taken = flags.io.deq.bits
    val id = jobs.deq.bits.token.rayId
    val same = taken.occ === t.occluded(id) && taken.err === t.errors(id) && taken.hit === t.hasHit(id)
    assert(!jobs.deq.fire || same, "leaf_job_flags: a job's table entries, read as it entered, have changed")
    taken
  }
}
