package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ErrorFlags}

/** A job's table entries, read as it enters LeafIntersect's job queue and kept until it is taken. */
class JobFlags extends Bundle {
  val occ = Bool()
  val err = UInt(ErrorFlags.width.W)
  val hit = Bool()
}

object JobFlags {

  /** The entries of the job at the head `job` of LeafIntersect's jobs, read as it entered at `enq`.
    *
    * Read when the job is taken, from the job queue's head, the select was the
    * unit's longest path (6.07 ns, docs/fmax.md). So each job's entries are
    * read in two stages ([[GroupedRead]]) as it enters, and written a cycle
    * after the job into a memory by its ray ID, which the take reads at the
    * head's ID. A job reaches the head register two cycles after it entered at
    * the earliest, so its entries are written by then. Kept in a queue beside
    * the jobs instead, the entries' write enable waited on the job queue's read
    * pointer through the take (6.02 ns). A ray has at most one job waiting
    * (each ray is in one place), so its entry is its job's until that job is
    * taken. A job's ray has no request outstanding and no clear can come for
    * it (a ray's clear comes before its first job, in an earlier cycle), so its
    * entries stand still from its entry until it is taken (checked:
    * `leaf_job_flags`).
    */
  def beside(cfg: AccelConfig, enq: DecoupledIO[LeafJob], job: DecoupledIO[LeafJob], t: LeafTables): JobFlags = {
    val enteredId = enq.bits.token.rayId
    val entered = Wire(new JobFlags)
    entered.occ := GroupedRead(t.occluded.map(_.asUInt), enteredId).asBool
    entered.err := GroupedRead(t.errors, enteredId)
    entered.hit := GroupedRead(t.hasHit.map(_.asUInt), enteredId).asBool
    val byId = Mem(cfg.numRayIds, new JobFlags)
    when(RegNext(enq.fire, false.B)) { byId.write(RegNext(enteredId), entered) }
    val id = job.bits.token.rayId
    val taken = byId.read(id)
    val same = taken.occ === t.occluded(id) && taken.err === t.errors(id) && taken.hit === t.hasHit(id)
    assert(!job.fire || same, "leaf_job_flags: a job's table entries, read as it entered, have changed")
    taken
  }
}
