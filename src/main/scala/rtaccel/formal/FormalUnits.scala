package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig
import rtaccel.leaf.{LeafIntersect, LeafJob}
import rtaccel.traversal.{PrepFetch, TraversalToken}

/** Per-unit bounded response (docs/formal.md, "Bounded response, unit by
  * unit"): the two units a ray waits in for memory, each alone in the
  * environment RtAccel gives it, with a bound derived from the configuration
  * that BMC checks past the bound itself.
  */
object UnitBound {

  /** PrepFetch: token in -> node out. The queue (a RamQueue: its head two
    * cycles after the token entered) is FIFO with at most n - 1 tokens ahead,
    * each taking <= S + 1 cycles to be taken by memory; then the answer
    * (<= L) and the output register (1).
    */
  def fetch(cfg: AccelConfig, env: FormalEnv): Int = cfg.numRayIds * (env.memStall + 1) + env.memLatency + 2

  /** LeafIntersect: job in -> exit out. Job queue 2 (a RamQueue's head); at most n - 1 jobs
    * ahead, each holding the issuer for its m requests (<= S + 1 cycles
    * each) or, stopped early (an empty leaf, an occluded shadow ray), until
    * its answers are drained (<= L + q + 2) and its exit gets the exit port
    * (the answer side goes first: <= n more); then its own m requests, the
    * last answer (<= L), register 1, triangle q, the exit register 1, the
    * exit queue (2, a RamQueue's head, and
    * <= n - 1 exits ahead, each <= 2 cycles: an exit with a hit leaves when
    * the tmax queue has room, which drains a write at least every 2 cycles,
    * a write losing at most one round to an entering ray), room in the tmax
    * queue for its own write (<= 2).
    */
  def leaf(cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv): Int = {
    val (n, m, s, l, q) = (cfg.numRayIds, cfg.maxLeafSize, env.memStall, env.memLatency, dp.primLatency)
    val issue = m * (s + 1)
    2 + (n - 1) * issue.max(l + q + 2 + n) + issue + l + 1 + q + 1 + 2 + 2 * (n - 1) + 2
  }
}

/** A per-ID monitor for a unit: `enter` a ray, `leave` it; asserts each
  * leaves only once it entered (`<name>_once`) and within `bound` cycles
  * (`<name>_bounded_response`); `inside(id)` feeds the environment's rule
  * that a ray is in one place.
  */
class UnitMonitor(n: Int, bound: Int, name: String) {
  val insideReg = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val ageReg = RegInit(VecInit(Seq.fill(n)(0.U(log2Ceil(bound + 2).W))))
  def watch(enter: Bool, enterId: UInt, leave: Bool, leaveId: UInt): Unit = {
    assert(!leave || insideReg(leaveId), s"${name}_once: a ray left that was not inside")
    for (i <- 0 until n) {
      val out = leave && leaveId === i.U
      when(enter && enterId === i.U) { insideReg(i) := true.B; ageReg(i) := 0.U }
      when(out) { insideReg(i) := false.B }
      when(insideReg(i) && !out && ageReg(i) <= bound.U) { ageReg(i) := ageReg(i) + 1.U }
      assert(!insideReg(i) || ageReg(i) < bound.U, s"${name}_bounded_response: ray $i inside for $bound cycles")
    }
  }
}

/** PrepFetch alone: free tokens (a ray's ID only when that ray is not inside,
  * as in RtAccel where each ray is in one place), a memory answering within
  * L, refusing at most S cycles in a row.
  */
class FormalFetchTop(cfg: AccelConfig, env: FormalEnv, bound: Int, tag: String) extends Module {
  val io = IO(new Bundle {})
  override def desiredName = s"FormalTop_$tag"
  private val fetch = Module(new PrepFetch(cfg))
  private val mem = Module(new FormalMemEnv(fetch.io.mem.p, env.memLatency, env.memStall))
  mem.io.mem <> fetch.io.mem
  fetch.io.nodeBase := 0.U
  private val mon = new UnitMonitor(cfg.numRayIds, bound, "fetch")
  fetch.io.in.valid := FormalAnySeq(Bool())
  fetch.io.in.bits := FormalAnySeq(new TraversalToken(cfg))
  assume(!(fetch.io.in.valid && mon.insideReg(fetch.io.in.bits.rayId)), "fetch_env_one_place")
  // The queue holds numRayIds: with each ray in one place it is never full.
  assert(!fetch.io.in.valid || fetch.io.in.ready, "fetch_in_ready: PrepFetch refused a ray")
  mon.watch(fetch.io.in.fire, fetch.io.in.bits.rayId, fetch.io.out.valid, fetch.io.out.bits.token.rayId)
}

/** LeafIntersect alone, in the environment RtAccel gives it: free jobs (a
  * ray's ID only when that ray is not inside; at most maxLeafSize
  * triangles), free triangle answers and ray data, a triangle memory within
  * L and S, exits always taken (Traversal's leafIn is always ready), the
  * tmax write refused at most one cycle in a row (the RayBuffer's
  * round-robin port, shared with entering rays), `clear` only for rays not
  * inside and never beside the ray's job, a ray's shadow bit fixed between
  * clears.
  */
class FormalLeafTop(cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv, bound: Int, tag: String) extends Module {
  val io = IO(new Bundle {})
  override def desiredName = s"FormalTop_$tag"
  private val leaf = Module(new LeafIntersect(cfg, dp.gen, () => dp.prim(cfg)))
  private val mem = Module(new FormalMemEnv(leaf.io.mem.p, env.memLatency, env.memStall))
  mem.io.mem <> leaf.io.mem
  leaf.io.triBase := 0.U
  leaf.io.rayRead.statics := FormalAnySeq(chiselTypeOf(leaf.io.rayRead.statics))
  leaf.io.rayRead.tmax := FormalAnySeq(chiselTypeOf(leaf.io.rayRead.tmax))
  leaf.io.resultId := FormalAnySeq(chiselTypeOf(leaf.io.resultId))
  leaf.io.resultLoad := FormalAnySeq(Bool())
  leaf.io.peerRead.valid := false.B // no other RayBuffer reader here
  leaf.io.peerRead.bits := 0.U
  leaf.io.out.ready := true.B
  private val mon = new UnitMonitor(cfg.numRayIds, bound, "leaf")
  leaf.io.in.valid := FormalAnySeq(Bool())
  leaf.io.in.bits := FormalAnySeq(new LeafJob(cfg))
  assume(!(leaf.io.in.valid && mon.insideReg(leaf.io.in.bits.token.rayId)), "leaf_env_one_place")
  assume(leaf.io.in.bits.count <= cfg.maxLeafSize.U, "leaf_env_size")
  leaf.io.clear.valid := FormalAnySeq(Bool())
  leaf.io.clear.bits := FormalAnySeq(chiselTypeOf(leaf.io.clear.bits))
  assume(!(leaf.io.clear.valid && mon.insideReg(leaf.io.clear.bits)), "leaf_env_clear")
  // LeafIntersect's contract (io.clear): a ray's clear comes in a cycle before its job, never beside it.
  assume(
    !(leaf.io.clear.valid && leaf.io.in.valid && leaf.io.clear.bits === leaf.io.in.bits.token.rayId),
    "leaf_env_clear_before_job"
  )
  // A ray is a shadow ray or not for its whole life: every job of an ID between two clears carries the
  // shadow bit of the first (LeafIntersect keeps a shadow ray's hit as occluded, `leaf_shadow_occluded`).
  private val shadowKnownReg = RegInit(VecInit(Seq.fill(cfg.numRayIds)(false.B)))
  private val shadowReg = Reg(Vec(cfg.numRayIds, Bool()))
  private val jobId = leaf.io.in.bits.token.rayId
  assume(
    !(leaf.io.in.valid && shadowKnownReg(jobId)) || leaf.io.in.bits.token.shadow === shadowReg(jobId),
    "leaf_env_shadow_fixed"
  )
  when(leaf.io.in.fire) { shadowKnownReg(jobId) := true.B; shadowReg(jobId) := leaf.io.in.bits.token.shadow }
  when(leaf.io.clear.valid) { shadowKnownReg(leaf.io.clear.bits) := false.B }
  private val tmaxRefusedReg = RegInit(false.B)
  leaf.io.tmax.ready := FormalAnySeq(Bool()) || tmaxRefusedReg
  tmaxRefusedReg := leaf.io.tmax.valid && !leaf.io.tmax.ready
  assert(!leaf.io.in.valid || leaf.io.in.ready, "leaf_in_ready: LeafIntersect refused a job")
  assert(!leaf.io.broken, "no_overflow_leaf_exit: a ray's last answer found the exit queue full")
  mon.watch(leaf.io.in.fire, leaf.io.in.bits.token.rayId, leaf.io.out.fire, leaf.io.out.bits.token.rayId)
}
