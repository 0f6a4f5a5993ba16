package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ErrorFlags, NodeLinks}

/** Where a ray goes after TraversalControl. TRAVERSE and GOBACK both lead to
  * a node fetch (the near child, or the node popped off the stack); they are
  * kept apart for the performance counters.
  */
object TraversalState extends ChiselEnum {
  val Traverse, Leaf, GoBack, Done = Value
}

class ControlIn(cfg: AccelConfig) extends Bundle {
  val token    = new TraversalToken(cfg)
  /** Back from LeafIntersect (`links` and `boxHit` are then ignored). */
  val fromLeaf = Bool()
  /** With `fromLeaf`: a shadow ray found an occluder, so it is finished. */
  val occluded = Bool()
  /** The ray hit the box of node `token.nodeIdx`, whose links these are. */
  val boxHit   = Bool()
  val links    = new NodeLinks(cfg)
}

class ControlOut(cfg: AccelConfig) extends Bundle {
  val state     = TraversalState()
  /** Updated token: `nodeIdx` is the node to fetch next (TRAVERSE/GOBACK). */
  val token     = new TraversalToken(cfg)
  val leafFirst = UInt(cfg.triIndexBits.W)
  val leafCount = UInt(cfg.leafCountBits.W)
}

/** One traversal decision per cycle, for whichever ray arrives:
  *  - box hit, inner node: TRAVERSE to the near child, pushing the far one;
  *  - box hit, leaf: LEAF, to LeafIntersect;
  *  - box miss, or back from a leaf: GOBACK to the popped node, or DONE when
  *    the stack is empty;
  *  - any error flag: DONE, so the ray returns with its flag set.
  * A push onto a full stack sets StackOverflow and ends the ray; no subtree is
  * ever dropped silently.
  *
  * Latency 1: the decision and the stack access happen in the input cycle;
  * the output (with the popped value, read synchronously) the next cycle. A
  * ray is never in this unit twice at once, so consecutive accesses belong to
  * different rays and there is no read-after-write hazard on a stack.
  */
class TraversalControl(cfg: AccelConfig) extends Module {
  val io = IO(new Bundle {
    val in  = Flipped(Valid(new ControlIn(cfg)))
    val out = Valid(new ControlOut(cfg))
  })
  override def desiredName = s"TraversalControl_n${cfg.numRayIds}_d${cfg.stackDepth}"

  private val stack = Module(new RayStack(cfg))
  private val in    = io.in.bits
  private val tok   = in.token
  private val links = in.links

  private val errorsIn  = tok.errors | Mux(in.fromLeaf, 0.U, links.errors)
  private val descend   = !in.fromLeaf && in.boxHit && !links.isLeaf
  private val enterLeaf = !in.fromLeaf && in.boxHit && links.isLeaf
  private val stackFull = tok.sp === cfg.stackDepth.U
  private val stackEmpty = tok.sp === 0.U
  private val errors    = errorsIn | Mux(descend && stackFull, ErrorFlags.bit(ErrorFlags.StackOverflow), 0.U)
  private val finished  = errors.orR || (in.fromLeaf && in.occluded) || (!descend && !enterLeaf && stackEmpty)

  private val state = Wire(TraversalState())
  state := Mux(finished, TraversalState.Done,
    Mux(descend, TraversalState.Traverse, Mux(enterLeaf, TraversalState.Leaf, TraversalState.GoBack)))

  // Near child first: left (= this node + 1) unless the ray runs toward
  // negative coordinates along the split axis.
  private val left     = tok.nodeIdx + 1.U
  private val rightNear = tok.dirNeg(links.axis)
  private val near     = Mux(rightNear, links.rightChild, left)
  private val far      = Mux(rightNear, left, links.rightChild)

  private val doPush = io.in.valid && state === TraversalState.Traverse
  private val doPop  = io.in.valid && state === TraversalState.GoBack
  stack.io.en      := doPush || doPop
  stack.io.isPush  := doPush
  stack.io.rayId   := tok.rayId
  stack.io.slot    := Mux(doPush, tok.sp, tok.sp - 1.U)
  stack.io.pushVal := far

  private val next = Wire(new ControlOut(cfg))
  next.state        := state
  next.token        := tok
  next.token.errors := errors
  next.token.sp     := MuxLookup(state.asUInt, tok.sp)(Seq(
    TraversalState.Traverse.asUInt -> (tok.sp + 1.U),
    TraversalState.GoBack.asUInt   -> (tok.sp - 1.U)))
  next.token.nodeIdx := Mux(state === TraversalState.Traverse, near, tok.nodeIdx)
  next.leafFirst    := links.first
  next.leafCount    := links.count

  private val outReg = RegEnable(next, io.in.valid)
  io.out.valid := RegNext(io.in.valid, false.B)
  io.out.bits  := outReg
  when(outReg.state === TraversalState.GoBack) { io.out.bits.token.nodeIdx := stack.io.popVal }
}
