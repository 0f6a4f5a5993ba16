package rtaccel

import chisel3._
import chisel3.util._
import rtaccel.fetch.{FetchBVH, RayIn}
import rtaccel.leaf.LeafIntersect
import rtaccel.mem.{MemPort, TaggedPortArbiter}
import rtaccel.system.HeadQueue
import rtaccel.traversal.{InitTraversal, PrepFetch, RayBuffer, Traversal, TraversalState}

/** The accelerator: rays in, one hit per ray out (docs/architecture.md).
  *
  * Two memory ports: nodes (FetchBVH's root fetch and Traversal's node
  * fetches, round-robin, tagged by source) and triangles (LeafIntersect).
  * Both response channels are always ready. `nodeBase` and `triBase` are the
  * byte addresses of node 0 and triangle 0 (from the memory image header);
  * change them only when no ray is in flight.
  */
class RtAccel[T <: Data](val cfg: AccelConfig, val dp: Datapath[T]) extends Module {
  private val nodeArb = Module(new TaggedPortArbiter(PrepFetch.port(cfg), 2))
  val io = IO(new Bundle {
    val rays = Flipped(Decoupled(new RayIn))
    val hits = Decoupled(new HitOut(cfg))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val triBase = Input(UInt(cfg.addrBits.W))
    val nodeMem = new MemPort(nodeArb.shared)
    val triMem = new MemPort(LeafIntersect.port(cfg))
    val perf = Output(new PerfCounters)

    /** Sticky: a ray was lost or duplicated (an enqueue found its queue full, or
      * an ID was freed twice). Never set; the harnesses fail at once if it is. */
    val broken = Output(Bool())
  })
  override def desiredName = s"RtAccel_k${cfg.boxLanes}_${dp.name}_n${cfg.numRayIds}_d${cfg.stackDepth}"

  private val fetch = Module(new FetchBVH(cfg, dp))
  private val init = Module(new InitTraversal(cfg, dp.gen))
  private val trav = Module(new Traversal(cfg, dp))
  private val leaf = Module(new LeafIntersect(cfg, dp.gen, () => dp.prim(cfg)))
  private val rayBuf = Module(new RayBuffer(cfg, dp.gen, readers = 2))

  fetch.io.rays <> io.rays
  fetch.io.nodeBase := io.nodeBase
  trav.io.nodeBase := io.nodeBase
  leaf.io.triBase := io.triBase
  nodeArb.io.clients(0) <> fetch.io.mem
  nodeArb.io.clients(1) <> trav.io.mem
  io.nodeMem <> nodeArb.io.mem
  io.triMem <> leaf.io.mem

  init.io.in := fetch.io.prepared
  init.io.root := fetch.io.root
  rayBuf.io.enter <> init.io.enter
  rayBuf.io.update <> leaf.io.tmax
  rayBuf.io.read(0) <> trav.io.rayRead
  rayBuf.io.read(1) <> leaf.io.rayRead
  leaf.io.peerRead.valid := trav.io.rayRead.en
  leaf.io.peerRead.bits := trav.io.rayRead.rayId
  trav.io.entry <> init.io.out
  leaf.io.in <> trav.io.leafOut
  trav.io.leafIn <> leaf.io.out
  // A ray's leaf tables are cleared a cycle after its ID is handed out: its first answer is RayPrep's and a
  // traversal step's latency away, and its ID's last ray has left. Registered, the clear does not carry the
  // free list's valid through the fetch handshake into LeafIntersect's read-ahead, the control's longest
  // path (docs/fmax.md).
  leaf.io.clear := Pipe(fetch.io.started)

  // ---- Output: one hit per finished ray, then its ID goes back ----
  // A register stage between Traversal's done lanes and the hit: without it the lanes' arbiter, the result
  // tables' read by ID, the number's lookup and the hit port follow each other in one cycle, the core control's
  // longest path (docs/fmax.md). Two entries keep one hit per cycle; a ray in it counts as held (below). Its
  // head is a register, so the reads below start from one.
  private val doneQ = Module(new HeadQueue(chiselTypeOf(trav.io.done.bits)))
  doneQ.io.enq <> trav.io.done
  private val done = doneQ.io.deq
  // The output stage: the head's has-hit flag, best hit and number are read by its ID into registers, and
  // the hit is driven from them. Read into the hit's fields in one cycle, the 1-of-n has-hit read was the
  // core control's longest path (docs/fmax.md). One cycle per hit; one hit per cycle. A ray here keeps its
  // ID until its hit leaves, so its entries stand still while they are read.
  private val outValidReg = RegInit(false.B)
  private val load = !outValidReg || io.hits.ready
  private val id = done.bits.rayId
  leaf.io.resultId := id
  leaf.io.resultLoad := load
  fetch.io.numberId := id
  private val outIdReg = RegEnable(id, load)
  private val outNumberReg = RegEnable(fetch.io.number, load)
  private val outErrorsReg = RegEnable(done.bits.errors, load)
  private val outOkReg = RegEnable(done.bits.errors === 0.U, load)
  when(load) { outValidReg := done.valid }
  done.ready := load
  private val best = leaf.io.result
  private val h = io.hits.bits
  h.number := outNumberReg
  h.hit := outOkReg && best.valid
  h.t := Mux(h.hit, dp.toFloat32(cfg, best.bits.t), 0.U)
  h.u := Mux(h.hit, dp.toFloat32(cfg, best.bits.u), 0.U)
  h.v := Mux(h.hit, dp.toFloat32(cfg, best.bits.v), 0.U)
  h.prim := Mux(h.hit, best.bits.prim, 0.U)
  h.errors := outErrorsReg
  io.hits.valid := outValidReg
  fetch.io.free.valid := io.hits.fire
  fetch.io.free.bits := outIdReg
  io.broken := trav.io.overflow || fetch.io.doubleFree || init.io.broken || leaf.io.broken
  // Checked in every simulation and proved by `make formal` (docs/formal.md).
  // Here, not in the units: their own specs drive these flags on purpose.
  assert(!trav.io.overflow, "no_overflow_traversal: a Traversal queue took an enqueue while full")
  assert(!init.io.broken, "no_overflow_init: a prepared ray found InitTraversal's queue full")
  assert(!leaf.io.broken, "no_overflow_leaf_exit: a ray's last answer found LeafIntersect's exit queue full")
  assert(!fetch.io.doubleFree, "id_freed_once: a hit returned an ID that was not in flight")
  // Each ray in flight is in exactly one unit: the counts of what each holds
  // sum to the free list's in-flight count (docs/formal.md: the invariant
  // behind "no queue overflows", stated so that induction can use it).
  // The rays in the done queue, counted as they pass (HeadQueue keeps no count).
  private val doneCountReg = RegInit(0.U(2.W))
  doneCountReg := doneCountReg + doneQ.io.enq.fire.asUInt - doneQ.io.deq.fire.asUInt
  // A ray whose hit left last cycle: the free list counts its free a cycle later (RayIdFreeList's `lateCheck`).
  private val freeingReg = RegNext(io.hits.fire, false.B)
  private val held =
    fetch.io.held +& init.io.held +& trav.io.held +& leaf.io.held +& doneCountReg +& outValidReg +& freeingReg
  assert(held === fetch.io.inFlight, "ray_conservation: the rays the units hold differ from the IDs in flight")

  // ---- Performance counters (64 bits, each exact every cycle: PerfCounter) ----
  private def count(event: Bool): UInt = PerfCounter(event.asUInt)
  private val p = io.perf
  p.cycles := count(true.B)
  p.raysIn := count(io.rays.fire)
  p.hitsOut := count(io.hits.fire)
  p.nodeFetches := count(io.nodeMem.req.fire)
  p.triFetches := count(io.triMem.req.fire)
  p.boxTests := count(trav.io.boxTests)
  // The counts that add a sum (the used child boxes, the rays in flight) take it a cycle late, from a register:
  // the sum's chain followed by the counter's low add was the core control's longest path (7.49 ns for the rays
  // in flight, 5.59 ns for the child boxes; docs/fmax.md). Over a batch the totals are the same (neither moves in
  // the cycles around START or after the last ray).
  private def late(x: UInt): UInt = { val r = RegInit(0.U(x.getWidth.W)); r := x; r }
  p.childBoxTests := PerfCounter(late(trav.io.childBoxes))
  p.leafReturns := count(trav.io.control(1).valid)
  p.triTests := count(leaf.io.tested)
  p.decisions := PerfCounter(trav.io.control(0).valid.asUInt +& trav.io.control(1).valid.asUInt)
  p.nodePortStall := count(io.nodeMem.req.valid && !io.nodeMem.req.ready)
  p.triPortStall := count(io.triMem.req.valid && !io.triMem.req.ready)
  p.raysInStall := count(io.rays.valid && !io.rays.ready)
  p.hitsOutStall := count(io.hits.valid && !io.hits.ready)
  p.inFlightSum := PerfCounter(late(fetch.io.inFlight))
}
