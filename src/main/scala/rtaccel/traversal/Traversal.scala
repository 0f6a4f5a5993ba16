package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.leaf.{LeafExit, LeafJob}
import rtaccel.mem.MemPort
import rtaccel.{AccelConfig, BvhNode, Datapath}

/** The traversal loop: box test → decision → node fetch → box test …
  *
  *  - Box stage: node answers from PrepFetch take priority over new rays
  *    from InitTraversal (which bring the on-chip root), since answers cannot
  *    wait (the memory is never back-pressured). The ray is read from the
  *    RayBuffer in the selection cycle and meets its node at BboxIntersect
  *    one cycle later, which tests all of the node's child boxes at once.
  *  - Box results wait in a queue, then share TraversalControl round-robin with
  *    rays coming back from leaves.
  *  - TRAVERSE/GOBACK go to PrepFetch, LEAF to LeafIntersect, DONE out.
  *
  * Every queue holds `numRayIds` entries and each ray is in one place, so no
  * enqueue can find a queue full; `overflow` would flag it if it ever did.
  */
class Traversal[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val io = IO(new Bundle {
    val entry    = Flipped(Decoupled(new EntryToken(cfg)))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem      = new MemPort(PrepFetch.port(cfg))
    val rayRead  = Flipped(new RayBufferRead(cfg, dp.gen))
    val leafOut  = Decoupled(new LeafJob(cfg))
    val leafIn   = Flipped(Decoupled(new LeafExit(cfg)))
    val done     = Decoupled(new TraversalToken(cfg))
    /** Sticky: some enqueue found its queue full (cannot happen; see above). */
    val overflow = Output(Bool())
    /** Performance counter inputs: a node tested, and how many used child boxes it had. */
    val boxTests = Output(Bool())
    val childBoxes = Output(UInt(log2Ceil(cfg.boxLanes + 1).W))
    /** A decision, and whether it was for a ray back from a leaf. */
    val control  = Output(Valid(TraversalState()))
    val leafReturn = Output(Bool())
    val fetchWaiting = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))
  })
  override def desiredName = s"Traversal_k${cfg.boxLanes}_n${cfg.numRayIds}_${dp.name}"

  private val fetch = Module(new PrepFetch(cfg))
  fetch.io.nodeBase := io.nodeBase
  io.mem <> fetch.io.mem
  io.fetchWaiting := fetch.io.waiting

  // ---- Box stage ----
  class AtNode extends Bundle {
    val token = new TraversalToken(cfg)
    val node  = new BvhNode(cfg)
  }
  private val fromMem = fetch.io.out
  io.entry.ready := !fromMem.valid
  private val pick = Wire(new AtNode)
  pick.token := Mux(fromMem.valid, fromMem.bits.token, io.entry.bits.token)
  pick.node  := Mux(fromMem.valid, fromMem.bits.node, io.entry.bits.root)
  private val picked = fromMem.valid || io.entry.valid
  io.rayRead.en    := picked
  io.rayRead.rayId := pick.token.rayId
  private val atNode = Pipe(picked, pick, 1)

  private val box = Module(new BboxIntersect(cfg, dp))
  private val slots = atNode.bits.node.slots
  box.io.in.valid        := atNode.valid
  box.io.in.bits.ray     := io.rayRead.statics
  box.io.in.bits.tmax    := io.rayRead.tmax
  box.io.in.bits.boxMin  := VecInit(slots.map(_.boxMin))
  box.io.in.bits.boxMax  := VecInit(slots.map(_.boxMax))
  box.io.in.bits.present := VecInit(slots.map(_.present))
  private val tested = Pipe(atNode.valid, atNode.bits, box.latency)
  io.boxTests   := box.io.out.valid
  io.childBoxes := Mux(box.io.out.valid, PopCount(tested.bits.node.slots.map(_.present)), 0.U)

  // ---- Decision ----
  private val boxDone = Module(new Queue(new ControlIn(cfg), cfg.numRayIds))
  private val b = boxDone.io.enq.bits
  boxDone.io.enq.valid := box.io.out.valid
  b.token      := tested.bits.token
  b.fromLeaf   := false.B
  b.occluded   := false.B
  b.hit        := box.io.out.bits.hit
  b.near       := box.io.out.bits.near
  b.refs       := VecInit(tested.bits.node.slots.map(_.child))
  b.axis       := tested.bits.node.axis
  b.nodeErrors := tested.bits.node.errors

  private val fromLeaf = Wire(Decoupled(new ControlIn(cfg)))
  fromLeaf.valid         := io.leafIn.valid
  fromLeaf.bits          := DontCare
  fromLeaf.bits.token    := io.leafIn.bits.token
  fromLeaf.bits.fromLeaf := true.B
  fromLeaf.bits.occluded := io.leafIn.bits.occluded
  fromLeaf.bits.hit      := VecInit(Seq.fill(cfg.boxLanes)(false.B))
  fromLeaf.bits.nodeErrors := 0.U
  io.leafIn.ready        := fromLeaf.ready

  private val arb = Module(new RRArbiter(new ControlIn(cfg), 2))
  arb.io.in(0) <> boxDone.io.deq
  arb.io.in(1) <> fromLeaf
  arb.io.out.ready := true.B
  private val control = Module(new TraversalControl(cfg))
  control.io.in.valid := arb.io.out.valid
  control.io.in.bits  := arb.io.out.bits
  io.control.valid := control.io.out.valid
  io.control.bits  := control.io.out.bits.state
  io.leafReturn    := arb.io.out.valid && arb.io.out.bits.fromLeaf

  // ---- Routing ----
  private val out   = control.io.out
  private val state = out.bits.state
  private val toFetch = out.valid && (state === TraversalState.Traverse || state === TraversalState.GoBack)
  fetch.io.in.valid := toFetch
  fetch.io.in.bits  := out.bits.token

  private val leafQ = Module(new Queue(new LeafJob(cfg), cfg.numRayIds))
  leafQ.io.enq.valid      := out.valid && state === TraversalState.Leaf
  leafQ.io.enq.bits.token := out.bits.token
  leafQ.io.enq.bits.first := out.bits.leafFirst
  leafQ.io.enq.bits.count := out.bits.leafCount
  io.leafOut <> leafQ.io.deq

  private val doneQ = Module(new Queue(new TraversalToken(cfg), cfg.numRayIds))
  doneQ.io.enq.valid := out.valid && state === TraversalState.Done
  doneQ.io.enq.bits  := out.bits.token
  io.done <> doneQ.io.deq

  private val overflowReg = RegInit(false.B)
  when((boxDone.io.enq.valid && !boxDone.io.enq.ready) || (toFetch && !fetch.io.in.ready) ||
    (leafQ.io.enq.valid && !leafQ.io.enq.ready) || (doneQ.io.enq.valid && !doneQ.io.enq.ready)) {
    overflowReg := true.B
  }
  io.overflow := overflowReg
}
