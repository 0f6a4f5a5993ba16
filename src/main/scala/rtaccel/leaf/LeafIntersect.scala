package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.fp.FpOrder
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.system.{HeadQueue, RamQueue}
import rtaccel.traversal.{RayBufferRead, TmaxUpdate, TraversalToken}
import rtaccel.{AccelConfig, ErrorFlags, HeldCount}

object LeafIntersect {

  /** Triangle requests are tagged with the ray ID. */
  def port(cfg: AccelConfig): MemPortParams = MemPortParams(cfg.addrBits, cfg.rayIdBits, TriangleRecord.RecordBytes)
}

/** Tests a ray against every triangle of a leaf and keeps its closest hit.
  *
  *  - Issue: one leaf at a time, one triangle request per cycle, tagged with
  *    the ray ID. A shadow ray that has found an occluder stops issuing.
  *  - Answer: each triangle goes through `PrimIntersect` (II = 1) with the ray read
  *    from the RayBuffer, and is reduced into the ray's best hit: smallest t,
  *    ties to the smaller prim, a total order, so the result does not depend
  *    on the order memory answers in.
  *  - Exit: a ray leaves when every request it issued has been reduced, never
  *    earlier, so its ID is never reused while memory still owes it data. Its
  *    new tmax is written to the RayBuffer as it leaves, through a two-entry
  *    queue, and lands before the ray's next RayBuffer read, so its next box
  *    test sees it (the golden model relies on that; `leaf_tmax_first`).
  *
  * Timing (docs/fmax.md): no 1-of-`numRayIds` table read is made in one
  * cycle. The reduce stage's entries (hit, occluded, errors, last
  * outstanding answer) are read over the answer pipe's two stages before it
  * into registers, with those cycles' own writes forwarded, and its best hit
  * a stage before it ([[LeafReadAhead]]); the best hit's write lands a cycle
  * after its answer, forwarded to every read until then; a job's entries are read as it
  * enters the job queue and kept by its ray ID until it is taken ([[JobFlags.beside]]), from the queue's head register
  * ([[rtaccel.system.RamQueue]]); the issuing ray keeps its entries in
  * registers beside `issueIdReg`. Cycle for cycle the unit behaves as if it read the tables
  * directly (assertions `leaf_done_view`, `leaf_issue_view` check it).
  *
  * The job and exit queues hold up to `numRayIds` entries, and each ray is in
  * one place, so neither can overflow and the response channel is always
  * ready; the two-entry tmax queue takes an entry only when it has room. The
  * exits enter `exits` through a register and cannot wait there: checked,
  * `broken` latches if one ever found the queue full.
  */
class LeafIntersect[T <: Data](cfg: AccelConfig, gen: T, mkPrim: () => PrimIntersect[T]) extends Module {
  val port: MemPortParams = LeafIntersect.port(cfg)
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new LeafJob(cfg)))
    val triBase = Input(UInt(cfg.addrBits.W))
    val mem = new MemPort(port)
    val rayRead = Flipped(new RayBufferRead(cfg, gen))
    val out = Decoupled(new LeafExit(cfg))
    val tmax = Decoupled(new TmaxUpdate(cfg))

    /** A ray enters the accelerator: forget any hit of the ID's previous ray. It comes in a cycle before the
      * ray's first job (RtAccel clears a cycle after the ID is handed out, RayPrep's latency and a traversal
      * step before any job), never while the ray is inside this unit.
      */
    val clear = Flipped(Valid(UInt(cfg.rayIdBits.W)))

    /** The best hit of a finished ray for RtAccel's output stage: `result` holds `resultId`'s has-hit flag and
      * best hit as they stood in the last cycle with `resultLoad` set. The 1-of-`numRayIds` read ends in these
      * registers: read into the hit output's fields in one cycle, it was the core control's longest path.
      */
    val resultId = Input(UInt(cfg.rayIdBits.W))
    val resultLoad = Input(Bool())
    val result = Output(Valid(new BestHit(cfg)))

    /** Triangle tests done (performance counter input). */
    val tested = Output(Bool())

    /** Sticky: an exit found the exit queue full (a lost ray; cannot happen, see above). */
    val broken = Output(Bool())

    /** The other RayBuffer reader's read (Traversal's), for the assertion `leaf_tmax_first` only. */
    val peerRead = Input(Valid(UInt(cfg.rayIdBits.W)))

    /** Rays this unit holds now (RtAccel's ray_conservation assertion). */
    val held = Output(UInt(log2Ceil(3 * cfg.numRayIds + 1).W))
  })
  override def desiredName = s"LeafIntersect_n${cfg.numRayIds}"

  private val n = cfg.numRayIds
  // Both queues are RamQueues: their heads (`deq.valid`, `deq.bits`) are registers, so taking a job starts from
  // registers and an exit's handshake (`room`, from its hit bit) reaches no further than them. chisel3.util's Queue
  // in block RAM ran the reader's handshake into its read address: the job queue's valid through the take into
  // the issue registers (5.48 ns), the exit's hit bit through `room` into the exit queue's read-during-write
  // compare (6.88 ns alone, 7.18 ns in the core's control; docs/fmax.md). A job or an exit reaches its head two
  // cycles after it entered; one per cycle still.
  private val jobs = Module(new RamQueue(new LeafJob(cfg), n))
  private val exits = Module(new RamQueue(new QueuedExit(cfg), n))
  jobs.io.enq <> io.in
  private val job = jobs.io.deq

  private val parked = Mem(n, new TraversalToken(cfg))
  private val best = Mem(n, new BestHit(cfg))
  private val hasHitReg = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val occludedReg = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val leafErrorsReg = RegInit(VecInit(Seq.fill(n)(0.U(ErrorFlags.width.W))))

  // ---- Issue ----
  private val busyReg = RegInit(false.B)
  private val stoppingReg = RegInit(false.B) // done issuing, owes an exit from the issue side
  private val issueIdReg = Reg(UInt(cfg.rayIdBits.W))
  private val nextTriReg = Reg(UInt(cfg.triIndexBits.W))
  private val remainingReg = Reg(UInt(cfg.leafCountBits.W))

  // The issuing ray's view of the per-ID tables, kept beside issueIdReg so
  // that no 1-of-n table read sits in the issue and exit logic (the clock at
  // 128 IDs): loaded from the tables when its job is taken, then updated with
  // the tables by its own answers. Checked against the tables below.
  private val issueOccReg = RegInit(false.B) // occludedReg(issueIdReg)
  private val issueErrReg = RegInit(0.U(ErrorFlags.width.W)) // leafErrorsReg(issueIdReg)
  private val issueOutReg = RegInit(0.U(cfg.leafCountBits.W)) // counts.counts(issueIdReg)
  private val issueHitReg = RegInit(false.B) // hasHitReg(issueIdReg)

  private val stopEarly = busyReg && issueOccReg
  io.mem.req.valid := busyReg && !stopEarly
  // A power-of-two stride: the address is a shift, not a multiply.
  io.mem.req.bits.addr := io.triBase + (nextTriReg << log2Ceil(TriangleRecord.StrideBytes))
  io.mem.req.bits.tag := issueIdReg
  private val lastIssue = io.mem.req.fire && remainingReg === 1.U
  when(io.mem.req.fire) {
    nextTriReg := nextTriReg + 1.U
    remainingReg := remainingReg - 1.U
    when(lastIssue) { busyReg := false.B }
  }
  // The next leaf starts in the cycle of this one's last request, so
  // back-to-back leaves issue one triangle every cycle (no bubble).
  job.ready := (!busyReg || lastIssue) && !stoppingReg
  when(job.fire) {
    val j = job.bits
    parked.write(j.token.rayId, j.token)
    issueIdReg := j.token.rayId
    nextTriReg := j.first
    remainingReg := j.count
    busyReg := j.count =/= 0.U
    stoppingReg := j.count === 0.U // an empty leaf: straight out
  }
  when(stopEarly) { busyReg := false.B; stoppingReg := true.B }

  // ---- Answer: memory -> RayBuffer read -> PrimIntersect -> reduce ----
  io.mem.resp.ready := true.B
  io.rayRead.en := io.mem.resp.valid
  io.rayRead.rayId := io.mem.resp.bits.tag
  private val respValidReg = RegNext(io.mem.resp.valid, false.B)
  private val respReg = RegEnable(io.mem.resp.bits, io.mem.resp.valid)

  private val prim = Module(mkPrim())
  prim.io.in.valid := respValidReg
  prim.io.in.bits.ray := io.rayRead.statics
  prim.io.in.bits.tmax := io.rayRead.tmax
  prim.io.in.bits.triangle := respReg.data

  private val carryIn = Wire(new AnswerCarry(cfg))
  carryIn.rayId := respReg.tag
  carryIn.prim := TriangleRecord.prim(respReg.data)
  carryIn.bad := (for (v <- 0 until 3; a <- 0 until 3)
    yield ErrorFlags.nonFinite(TriangleRecord.vertexWord(respReg.data, v, a))).reduce(_ || _)
  // `pre`: the answer pipe one stage before `carry`, where the reduce stage's
  // per-ID table reads end (registered, with the cycle's own writes forwarded);
  // `pre2` one stage before that, where they begin (below, "two stages").
  require(prim.latency >= 1, "LeafIntersect: the table reads take the triangle unit's last two stages")
  private val (pre2Id, preId, carry) =
    if (prim.latency == 1) {
      // pre is respReg's stage; pre2 the response itself (respReg takes it when valid).
      val p = Pipe(respValidReg, carryIn, 0)
      (io.mem.resp.bits.tag, p.bits.rayId, Pipe(p, 1))
    } else {
      val p2 = Pipe(respValidReg, carryIn, prim.latency - 2)
      val p = Pipe(p2, 1)
      (p2.bits.rayId, p.bits.rayId, Pipe(p, 1))
    }
  io.tested := prim.io.out.valid

  private val doneId = carry.bits.rayId
  private val ans = prim.io.out.bits
  private val primIdx = carry.bits.prim(cfg.triIndexBits - 1, 0)
  private val primTooWide = if (cfg.triIndexBits >= 32) false.B else carry.bits.prim(31, cfg.triIndexBits).orR
  // One read port per consumer: every extra `read` replicates the memory.
  // The answered ray's token is read at the pre2 stage and registered twice, so it reaches the reduce stage from a
  // register: block RAM's first register is its own, and read at `doneId` its clock-to-out ran into the occluded
  // table's write enables (5.16 ns, docs/fmax.md). It stands still over those cycles: a ray with an answer in
  // flight has a request outstanding, so no job of its is taken and its entry is not written (`leaf_job_drained`).
  private val doneTok = RegNext(RegNext(parked.read(pre2Id)))
  private val issueTok = parked.read(issueIdReg)
  private val reduce = prim.io.out.valid
  private val writes = Wire(new LeafWrites(cfg))
  private val counts = new OutstandingCounts(n, cfg.leafCountBits, writes)
  // The best table's write, a cycle after its answer: the closer-hit compare ends in a register, not in the
  // table's write enables (mapped at 5.9 to 6.7 ns in some netlists, docs/fmax.md). Until it lands, every
  // read (the read-ahead, the exit's tmax, `result`) takes it from here (LeafTables.best).
  private val bestWrite = Wire(Valid(new BestWrite(cfg)))
  private val tables = LeafTables(hasHitReg, occludedReg, leafErrorsReg, counts, best, bestWrite)
  // Whether an ID at the pre stages is the issuing ray's, compared a cycle ahead: the pre stage's ID is the pre2
  // stage's a cycle before (and the reduce stage's the pre stage's), and the issuing ID is the taken job's or
  // stays. Both compares are registered and picked after the registers by whether a job was taken. Compared
  // in their own cycle, issueIdReg's compares ran through the exit's valid into the exit queue's write enables
  // (6.02 ns in the core's control) and through the read-ahead into `lastReg` (5.24 ns).
  private val tookReg = RegNext(job.fire, false.B)
  private def aheadIsIssuing(id: UInt): Bool =
    Mux(tookReg, RegNext(id === job.bits.token.rayId), RegNext(id === issueIdReg))
  private val incIsPre = aheadIsIssuing(pre2Id)
  // The tables as they stand for `doneId`, read a cycle ahead.
  private val done = new LeafReadAhead(cfg, tables, writes, pre2Id, preId, incIsPre)
  private val closer = !done.hasHitReg || done.closer(FpOrder.key(cfg.triFloat, ans.t), primIdx)
  // Any valid hit sets the ray's has-hit and occluded flags; only a closer one replaces its best. The two
  // differ only for a ray that has a hit already (`closer` holds when it has none), and then both flags are
  // set: a shadow ray's first hit sets both (asserted: leaf_shadow_occluded). So the flags, their forwards and
  // the exit's hit bit do not wait on the distance compare, which through the occluded table's read-ahead
  // was the unit's longest path (docs/fmax.md).
  private val anyHit = reduce && ans.hit && !primTooWide
  private val update = anyHit && closer
  private val occludes = anyHit && doneTok.shadow
  assert(!reduce || doneTok.rayId === doneId, "leaf_done_token: the reduce stage's token is another ray's")
  private val b = Wire(new BestHit(cfg))
  b.t := ans.t; b.u := ans.u; b.v := ans.v; b.prim := primIdx

  /** This cycle's error flags for `doneId`. */
  private val errNow = Mux(reduce && primTooWide, ErrorFlags.bit(ErrorFlags.IndexOverflow), 0.U) |
    Mux(reduce && carry.bits.bad, ErrorFlags.bit(ErrorFlags.BadSceneData), 0.U)
  bestWrite.valid := RegNext(update, false.B)
  bestWrite.bits.id := RegNext(doneId)
  bestWrite.bits.hit := RegNext(b)
  when(bestWrite.valid) { best.write(bestWrite.bits.id, bestWrite.bits.hit) }
  when(anyHit) {
    hasHitReg(doneId) := true.B
    when(doneTok.shadow) { occludedReg(doneId) := true.B }
  }
  // The ray's flags as the read-ahead has them (equal to the table's entry, `leaf_done_view`), not a 1-of-n read
  // of the table here: that read into the write mapped to 4 LUT and 3 MUXF in the core's control (4.94 ns).
  when(reduce && (primTooWide || carry.bits.bad)) {
    leafErrorsReg(doneId) := done.errorsReg | errNow
  }

  private val issuing = busyReg || stoppingReg
  private val isIssuing = aheadIsIssuing(preId)
  assert(
    !reduce || (isIssuing === (doneId === issueIdReg) && RegNext(incIsPre) === RegNext(issueIdReg === preId)),
    "leaf_done_issue: a compare with the issuing ID, made a cycle ahead, is wrong"
  )
  private val doneIssuing = reduce && isIssuing
  private val lastAnswer = reduce && done.lastReg && !(issuing && isIssuing)
  private val issueDrained = issueOutReg === 0.U || (issueOutReg === 1.U && doneIssuing)

  writes.inc := io.mem.req.fire
  writes.incId := issueIdReg
  writes.reduce := reduce
  writes.doneId := doneId
  writes.anyHit := anyHit
  writes.occludes := occludes
  writes.errors := errNow
  writes.update := update
  writes.best := b
  writes.clear := io.clear

  // ---- The issuing ray's view (see issueOccReg): a job's ray has no request
  // outstanding (it left its last leaf drained, and is in one place), so no
  // answer or clear can change its entries in the cycle its job is taken. ----
  issueOutReg := issueOutReg + io.mem.req.fire.asUInt - doneIssuing.asUInt
  when(doneIssuing && occludes) { issueOccReg := true.B }
  when(doneIssuing && anyHit) { issueHitReg := true.B }
  when(doneIssuing) { issueErrReg := issueErrReg | errNow }
  when(io.clear.valid && io.clear.bits === issueIdReg) {
    issueOccReg := false.B; issueErrReg := 0.U; issueHitReg := false.B
  }
  private val taken = JobFlags.beside(cfg, jobs.io.enq, job, tables)
  when(job.fire) {
    issueOutReg := 0.U
    issueOccReg := taken.occ
    issueErrReg := taken.err
    issueHitReg := taken.hit
  }
  assert(
    !job.fire || counts.counts(job.bits.token.rayId) === 0.U,
    "leaf_job_drained: a ray's job was taken while it still had triangle requests outstanding"
  )
  assert(
    !issuing || (issueOutReg === counts.counts(issueIdReg) && issueOccReg === occludedReg(issueIdReg) &&
      issueErrReg === leafErrorsReg(issueIdReg) && issueHitReg === hasHitReg(issueIdReg)),
    "leaf_issue_view: the issuing ray's registers differ from its table entries"
  )
  assert(
    !reduce || (done.lastReg === (counts.counts(doneId) === 1.U) && done.hasHitReg === hasHitReg(doneId) &&
      done.occludedReg === occludedReg(doneId) && done.errorsReg === leafErrorsReg(doneId)),
    // (not `best`: a fourth read port would replicate the memory; the specs compare every hit)
    "leaf_done_view: the reduce stage's registers differ from the answered ray's table entries"
  )
  assert(
    !(reduce && done.hasHitReg && doneTok.shadow) || done.occludedReg,
    "leaf_shadow_occluded: a shadow ray with a hit is not marked occluded"
  )

  // ---- Exit: the answer side first (it cannot wait), then the issue side ----
  // A ray's exit in the cycle of its last answer also carries that answer's
  // error flags (its table entry takes them only at the clock edge).
  // So does its hit: `anyHit` is that answer's has-hit write.
  // Either exit is registered before the exit queue, as its parts (ExitParts), a cycle per exit. The registered
  // exit always enters the queue, which holds `numRayIds` or more (each ray is in one place): checked, `broken`
  // latches if one ever found the queue full.
  private def partsOf(tok: TraversalToken, errors: UInt, occluded: Bool, hit: Bool, answered: Bool): ExitParts = {
    val p = Wire(new ExitParts(cfg))
    p.token := tok
    p.errors := errors | Mux(answered, errNow, 0.U)
    p.occluded := occluded
    p.answeredHit := answered && ans.hit
    p.hit := hit || (answered && anyHit)
    p
  }
  private val issueExit = stoppingReg && issueDrained && !lastAnswer
  private val exitIn = Pipe(
    lastAnswer || issueExit,
    Mux(
      lastAnswer,
      partsOf(doneTok, done.errorsReg, done.occludedReg, done.hasHitReg, reduce),
      partsOf(issueTok, issueErrReg, issueOccReg, issueHitReg, doneIssuing)
    ),
    1
  )
  exits.io.enq.valid := exitIn.valid
  exits.io.enq.bits := exitIn.bits.queued
  when(issueExit) { stoppingReg := false.B }
  private val brokenReg = RegInit(false.B)
  when(exitIn.valid && !exits.io.enq.ready) { brokenReg := true.B }
  io.broken := brokenReg

  // A ray with a hit leaves with its tmax write: the write enters a two-entry queue whose head and `enq.ready`
  // are registers (HeadQueue) as the exit leaves, and reaches the RayBuffer from there. Waiting for the write's
  // grant instead, the exit's valid followed InitTraversal's queue through the RayBuffer's write arbiter into
  // Traversal's control and stack (7.39 ns in the core's control, docs/fmax.md). An exit leaves only when the
  // queue has room, so the enqueue never overflows. The write lands a few cycles after the exit (through this
  // queue and TmaxRead's, each write losing at most one round of the RayBuffer's round-robin arbiter to an
  // entering ray), and the ray's next RayBuffer read is further away (a traversal decision and its lane
  // register, then a node fetch's or a triangle fetch's queue and answer): checked, `leaf_tmax_first`. A ray
  // with no hit yet keeps the tmax it entered with and writes nothing. Whether it has a hit travels in its
  // queue entry: a ray in `exits` gets no more answers, and its ID is not cleared before it leaves, so the bit
  // stays equal to hasHitReg (assertion `leaf_exit_hit`), and the handshake reads no 1-of-n table (read from
  // hasHitReg, the bit would be on the core control's longest path, docs/fmax.md).
  private val exitHead = exits.io.deq
  private val headId = exitHead.bits.exit.token.rayId
  private val tmaxQ = Module(new HeadQueue(UInt(cfg.rayIdBits.W)))
  private val room = !exitHead.bits.hasHit || tmaxQ.io.enq.ready
  io.out.valid := exitHead.valid && room
  io.out.bits := exitHead.bits.exit
  exitHead.ready := io.out.ready && room
  tmaxQ.io.enq.valid := io.out.fire && exitHead.bits.hasHit
  tmaxQ.io.enq.bits := headId
  io.tmax <> TmaxRead(cfg, tmaxQ.io.deq, best, bestWrite, tables.best(_).t)
  assert(
    !exitHead.valid || exitHead.bits.hasHit === hasHitReg(headId),
    "leaf_exit_hit: an exit's hit bit differs from its ray's table entry"
  )
  TmaxRead.checkFirst(
    n,
    tmaxQ.io.enq.fire -> headId,
    io.tmax.fire -> io.tmax.bits.rayId,
    Seq(
      io.rayRead.en -> io.rayRead.rayId,
      io.peerRead.valid -> io.peerRead.bits
    )
  )

  when(io.clear.valid) {
    hasHitReg(io.clear.bits) := false.B
    occludedReg(io.clear.bits) := false.B
    leafErrorsReg(io.clear.bits) := 0.U
  }
  // A finished ray's entries stand still until its hit has left (its ID is neither cleared nor given answers),
  // so RtAccel loads them with the ray's other output fields. The has-hit flag is a table of registers: its
  // groups' picks are loaded ([[GroupedRead.loaded]]) and ORed after them; as one 1-of-n select into a register
  // it mapped to 4 LUT and 3 MUXF (4.94 ns). The best hit is a memory read.
  private val resultBestReg = RegEnable(tables.best(io.resultId), io.resultLoad)
  io.result.valid := GroupedRead.loaded(hasHitReg.map(_.asUInt), io.resultId, io.resultLoad).asBool
  io.result.bits := resultBestReg

  // Waiting jobs, exits, and between them each ray issuing or owed answers.
  // The rays between are counted as they pass (taken from `jobs`; put into
  // `exits`, or lost by the checked enqueue above): a 128-wide popcount into
  // `held` was the unit's longest path. The popcount stays as an assertion
  // (simulation and formal only), as RayIdFreeList checks its in-flight count.
  private val working = (0 until n).map(i => counts.counts(i) =/= 0.U || (issuing && issueIdReg === i.U))
  private val betweenReg = RegInit(0.U(log2Ceil(n + 1).W))
  private val leaves = lastAnswer || issueExit
  betweenReg := betweenReg + job.fire.asUInt - leaves.asUInt
  assert(
    betweenReg === PopCount(working),
    "leaf_between_count: the rays counted between jobs and exits differ from the IDs issuing or owed answers"
  )
  // The unit's rays, counted as they enter and leave (HeldCount): the sum of the parts' counts into `held` was the
  // unit's longest path (5.82 ns). The sum stays as an assertion.
  private val heldCount = HeldCount(Seq(io.in.fire), Seq(io.out.fire), io.held.getWidth)
  assert(
    heldCount === jobs.io.count +& betweenReg +& exitIn.valid.asUInt +& exits.io.count,
    "leaf_held_count: the rays counted into and out of LeafIntersect differ from the sum of its parts"
  )
  io.held := heldCount
}
