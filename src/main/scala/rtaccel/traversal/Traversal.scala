package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.leaf.{LeafExit, LeafJob}
import rtaccel.mem.MemPort
import rtaccel.system.RamQueue
import rtaccel.{AccelConfig, Datapath, HeldCount}
import rtaccel.datapath.RayConsts
import rtaccel.bvh.BvhNode

/** The traversal loop: box test → decision → node fetch → box test …
  *
  *  - Box stage: node answers from PrepFetch take priority over new rays
  *    from InitTraversal (which bring the on-chip root), since answers cannot
  *    wait (the memory is never back-pressured). The ray is read from the
  *    RayBuffer in the selection cycle and meets its node at BboxIntersect
  *    one cycle later, which tests all of the node's child boxes at once
  *    (with grid box tests, GridBboxIntersect, in the quantized node's grid).
  *  - Box results go straight to TraversalControl's box-result lane; rays
  *    back from leaves take its leaf-return lane.
  *  - TRAVERSE/GOBACK go to PrepFetch, LEAF to LeafIntersect, DONE out, each
  *    lane through queues of its own, merged round-robin.
  *
  * Every queue holds `numRayIds` entries and each ray is in one place, so no
  * enqueue can find a queue full; `overflow` would flag it if it ever did.
  */
class Traversal[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val io = IO(new Bundle {
    val entry = Flipped(Decoupled(new EntryToken(cfg)))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem = new MemPort(PrepFetch.port(cfg))
    val rayRead = Flipped(new RayBufferRead(cfg, dp.gen))
    val leafOut = Decoupled(new LeafJob(cfg))
    val leafIn = Flipped(Decoupled(new LeafExit(cfg)))
    val done = Decoupled(new TraversalToken(cfg))

    /** Sticky: some enqueue found its queue full (cannot happen; see above). */
    val overflow = Output(Bool())

    /** Performance counter inputs: a node tested, and how many used child boxes it had. */
    val boxTests = Output(Bool())
    val childBoxes = Output(UInt(log2Ceil(cfg.boxLanes + 1).W))

    /** Decisions of the box-result lane (0) and the leaf-return lane (1). */
    val control = Output(Vec(2, Valid(TraversalState())))
    val fetchWaiting = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))

    /** Rays this unit holds now (RtAccel's ray_conservation assertion). */
    val held = Output(UInt(log2Ceil(9 * cfg.numRayIds + 32).W))
  })
  override def desiredName = s"Traversal_k${cfg.boxLanes}_n${cfg.numRayIds}_${dp.name}"

  private val fetch = Module(new PrepFetch(cfg))
  fetch.io.nodeBase := io.nodeBase
  io.mem <> fetch.io.mem
  io.fetchWaiting := fetch.io.waiting

  // ---- Box stage ----
  class AtNode extends Bundle {
    val token = new TraversalToken(cfg)
    val node = new BvhNode(cfg)
  }
  private val fromMem = fetch.io.out
  io.entry.ready := !fromMem.valid
  private val pick = Wire(new AtNode)
  pick.token := Mux(fromMem.valid, fromMem.bits.token, io.entry.bits.token)
  pick.node := Mux(fromMem.valid, fromMem.bits.node, io.entry.bits.root)
  private val picked = fromMem.valid || io.entry.valid
  io.rayRead.en := picked
  io.rayRead.rayId := pick.token.rayId
  private val atNode = Pipe(picked, pick, 1)

  private val slots = atNode.bits.node.slots
  // The box test: K FP32 box lanes, or (BoxTest.Grid) one FP32 stage per node and K integer lanes in its grid.
  private val (boxLatency, boxOut) = if (!cfg.gridBox) {
    val box = Module(new BboxIntersect(cfg, dp))
    box.io.in.valid := atNode.valid
    box.io.in.bits.ray := io.rayRead.statics
    box.io.in.bits.tmax := io.rayRead.tmax
    box.io.in.bits.boxMin := VecInit(slots.map(_.boxMin.get))
    box.io.in.bits.boxMax := VecInit(slots.map(_.boxMax.get))
    box.io.in.bits.present := VecInit(slots.map(_.present))
    (box.latency, box.io.out)
  } else {
    val rays = dp.gen match {
      case r: RayConsts => r
      case _ =>
        throw new IllegalArgumentException(
          s"Traversal: boxTest = ${cfg.boxTest.name} needs a float datapath's ray constants (RayConsts), not ${dp.name}'s"
        )
    }
    val grid = Module(new GridBboxIntersect(cfg.boxLanes, cfg.gridParams, rays))
    val g = atNode.bits.node.grid.get
    grid.io.in.valid := atNode.valid
    // The RayBuffer holds dp.gen, a RayConsts (matched above).
    grid.io.in.bits.node.ray := io.rayRead.statics.asInstanceOf[RayConsts]
    grid.io.in.bits.node.tmax := io.rayRead.tmax
    grid.io.in.bits.node.origin := g.origin
    grid.io.in.bits.node.exp := g.exp
    for ((c, s) <- grid.io.in.bits.children.zip(slots)) {
      c.qMin := s.qMin.get
      c.qMax := s.qMax.get
      c.present := s.present
    }
    // The grid's near is signed, relative to the node; TraversalControl orders it as such (nearBits).
    val out = Wire(Valid(new BboxAnswer(cfg)))
    out.valid := grid.io.out.valid
    out.bits.hit := grid.io.out.bits.hit
    out.bits.near := VecInit(grid.io.out.bits.near.map(_.asUInt))
    out.bits.order := TraversalControl.order(cfg, out.bits.near)
    (grid.latency, out)
  }
  private val tested = Pipe(atNode.valid, atNode.bits, boxLatency)
  io.boxTests := boxOut.valid
  io.childBoxes := Mux(boxOut.valid, PopCount(tested.bits.node.slots.map(_.present)), 0.U)

  // ---- Decision ----
  private val boxDone = Wire(Valid(new ControlIn(cfg)))
  private val b = boxDone.bits
  boxDone.valid := boxOut.valid
  b.token := tested.bits.token
  b.hit := boxOut.bits.hit
  b.order := boxOut.bits.order
  b.refs := VecInit(tested.bits.node.slots.map(_.child))
  b.axis := tested.bits.node.axis
  b.nodeErrors := tested.bits.node.errors

  // Box results go straight to the box-result lane (one per cycle, as they
  // leave BboxIntersect); rays back from leaves take the leaf-return lane,
  // one per cycle, so leafIn never waits.
  private val control = Module(new TraversalControl(cfg))
  control.io.in := boxDone
  control.io.ret.valid := io.leafIn.valid
  control.io.ret.bits.token := io.leafIn.bits.token
  control.io.ret.bits.occluded := io.leafIn.bits.occluded
  io.leafIn.ready := true.B

  // ---- Routing: each lane has its own queues (every one holds numRayIds, so
  // none can overflow: each ray is in one place), merged round-robin ----
  // A register between each lane's decision and its queues: the decision reads the ray stack,
  // and the stack's read through the decision into a queue's write enable maps to 10 LUTs
  // (8.52 ns, docs/fmax.md). A cycle per decision; the queues take one ray per lane per cycle.
  // The register takes the decision and the popped entry apart and combines them after it.
  private val lanes = Seq(control.io.out, control.io.retOut).map { d =>
    val r = Pipe(d)
    val o = Wire(Valid(new ControlOut(cfg)))
    o.valid := r.valid
    o.bits := TraversalControl.resolve(cfg, r.bits)
    o
  }
  // Decisions per lane, for the performance counters, as they leave the register.
  for ((c, o) <- io.control.zip(lanes)) { c.valid := o.valid; c.bits := o.bits.state }
  private def isFetch(o: Valid[ControlOut]) =
    o.valid && (o.bits.state === TraversalState.Traverse || o.bits.state === TraversalState.GoBack)
  private val fetchQs = lanes.map { o =>
    val q = Module(new RamQueue(new TraversalToken(cfg), cfg.numRayIds))
    q.io.enq.valid := isFetch(o); q.io.enq.bits := o.bits.token; q
  }
  private val leafQs = lanes.map { o =>
    val q = Module(new RamQueue(new LeafJob(cfg), cfg.numRayIds))
    q.io.enq.valid := o.valid && o.bits.state === TraversalState.Leaf
    q.io.enq.bits.token := o.bits.token
    q.io.enq.bits.first := o.bits.leafFirst
    q.io.enq.bits.count := o.bits.leafCount
    q
  }
  private val doneQs = lanes.map { o =>
    val q = Module(new RamQueue(new TraversalToken(cfg), cfg.numRayIds))
    q.io.enq.valid := o.valid && o.bits.state === TraversalState.Done; q.io.enq.bits := o.bits.token; q
  }
  // The queues are RamQueues, whose heads are registers: the round-robin grant and the sink's ready end in them.
  // Merged from chisel3.util Queues in block RAM, a queue's read pointer ran through the empty compare, the
  // arbiter's grant and its own increment into the RAM's read address (6.37 ns, docs/fmax.md).
  private def merge[D <: Data](qs: Seq[RamQueue[D]], sink: DecoupledIO[D]): Unit = {
    val arb = Module(new RRArbiter(chiselTypeOf(sink.bits), qs.size))
    for ((q, i) <- qs.zipWithIndex) arb.io.in(i) <> q.io.deq
    sink <> arb.io.out
  }
  merge(fetchQs, fetch.io.in)
  merge(leafQs, io.leafOut)
  merge(doneQs, io.done)

  private val overflowReg = RegInit(false.B)
  private val enqs = (fetchQs ++ leafQs ++ doneQs).map(_.io.enq)
  when(enqs.map(e => e.valid && !e.ready).reduce(_ || _)) { overflowReg := true.B }
  io.overflow := overflowReg

  // Box stage (atNode, the box pipe), control, the lane queues, PrepFetch
  // (its queue, memory, the answer register). The box pipe's rays are counted
  // as they enter and leave it: a popcount of its stages would be the unit's
  // longest path, for a count only assertions read. The popcount stays as an
  // assertion (simulation and formal only).
  private val inPipeReg = RegInit(0.U(log2Ceil(boxLatency + 1).max(1).W))
  inPipeReg := inPipeReg + atNode.valid.asUInt - tested.valid.asUInt
  assert(
    inPipeReg === PopCount(ShiftRegisters(atNode.valid, boxLatency, false.B, true.B)),
    "box_pipe_count: the rays counted in the box pipe differ from its valid stages"
  )
  private val inBox = atNode.valid +& inPipeReg
  private val queued = (fetchQs ++ leafQs ++ doneQs).map(_.io.count).reduce(_ +& _)
  // The unit's rays are counted the same way, as they enter (new rays, leaf returns) and leave (to LeafIntersect,
  // done): the sum of its parts' counts would be the unit's longest path (6.71 ns), for a count only assertions
  // read. The handshakes are registered before they are added: a leaf return's valid comes through RayBuffer's
  // write arbiter from InitTraversal, and that chain ending in the count's add is 8.15 ns in the control's
  // flattened netlist (docs/fmax.md). The sum stays as an assertion (simulation and formal only).
  private val held = HeldCount(Seq(io.entry.fire, io.leafIn.fire), Seq(io.leafOut.fire, io.done.fire), io.held.getWidth)
  assert(
    held === inBox +& control.io.held +& lanes.map(_.valid.asUInt).reduce(_ +& _) +& queued +& fetch.io.waiting +&
      fetch.io.out.valid,
    "traversal_held_count: the rays counted into and out of Traversal differ from the sum of its parts"
  )
  io.held := held
}
