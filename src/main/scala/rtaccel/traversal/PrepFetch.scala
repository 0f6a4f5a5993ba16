package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.system.RamQueue
import rtaccel.{AccelConfig, HeldCount}
import rtaccel.bvh.{BvhNode, NodeRecord, NodeWords}

/** Turns "ray `id` wants node `k`" into a node request tagged with `id`, and
  * each response back into (token, node).
  *
  * Tokens wait in a queue of `numRayIds` entries, which can never overflow
  * because each ray is in at most one place. While memory works, a ray's token
  * waits in a per-ray slot indexed by its ID, so responses can return in any
  * order. The response channel is always ready (docs/architecture.md: the
  * accelerator never back-pressures memory); the output is a valid pipe.
  */
class PrepFetch(cfg: AccelConfig) extends Module {
  val port: MemPortParams = PrepFetch.port(cfg)
  val io = IO(new Bundle {
    val in = Flipped(Decoupled(new TraversalToken(cfg)))

    /** Byte address of node 0 in memory. */
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem = new MemPort(port)
    val out = Valid(new FetchedNode(cfg))

    /** Rays waiting in the queue or for memory (a performance counter input). */
    val waiting = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))
  })
  override def desiredName = s"PrepFetch_k${cfg.boxLanes}_n${cfg.numRayIds}"

  private val queue = Module(new RamQueue(new TraversalToken(cfg), cfg.numRayIds))
  queue.io.enq <> io.in

  // The queue's head is a register (RamQueue), so the node address's add starts from a register: from a
  // chisel3.util Queue's block RAM it ran into the request's address (5.78 ns, docs/fmax.md).
  private val next = queue.io.deq
  private val parked = Mem(cfg.numRayIds, new TraversalToken(cfg))
  io.mem.req.valid := next.valid
  io.mem.req.bits.addr := io.nodeBase + PrepFetch.nodeOffset(cfg, next.bits.nodeIdx)
  io.mem.req.bits.tag := next.bits.rayId
  next.ready := io.mem.req.ready
  when(io.mem.req.fire) { parked.write(next.bits.rayId, next.bits) }

  io.mem.resp.ready := true.B
  private val fetched = Wire(new FetchedNode(cfg))
  class Answer[T <: Data](gen: T) extends Bundle {
    val token = new TraversalToken(cfg)
    val body = gen
  }
  private val answer = Wire(Valid(new Answer(new NodeRecord(cfg))))
  answer.valid := io.mem.resp.valid
  answer.bits.token := parked.read(io.mem.resp.bits.tag)
  // The ray ID is the answer's tag, taken from there rather than from the parked entry (equal: asserted). The
  // output register after the parked table is the block RAM's own output stage (Yosys, like Vivado, folds it in),
  // and the ID read from it ran through the box stage's pick into the RayBuffer's read address (5.16 ns in the
  // core's control, docs/fmax.md); from the tag it starts at a plain register.
  answer.bits.token.rayId := io.mem.resp.bits.tag
  assert(
    !io.mem.resp.valid || parked.read(io.mem.resp.bits.tag).rayId === io.mem.resp.bits.tag,
    "prep_fetch_tag: a node answer's tag differs from its parked ray's ID"
  )
  answer.bits.body := BvhNode.record(cfg, io.mem.resp.bits.data)
  // Quantized layouts: the record with its slots' counts, then its words (the child-index adders), are each
  // registered before the checks, two cycles more per node fetch (BvhNode.staged). The stages are valid pipes,
  // like the output: they never wait.
  private val recorded = if (BvhNode.staged(cfg)) Pipe(answer) else answer
  private val worded = Wire(Valid(new Answer(new NodeWords(cfg))))
  worded.valid := recorded.valid
  worded.bits.token := recorded.bits.token
  worded.bits.body := BvhNode.words(cfg, recorded.bits.body)
  private val decoded = if (BvhNode.staged(cfg)) Pipe(worded) else worded
  fetched.token := decoded.bits.token
  fetched.node := BvhNode.fields(cfg, decoded.bits.body)
  io.out := Pipe(decoded.valid, fetched, 1)
  // The slots' checks (compares of whole words) are registered with the node and combined into its error flags
  // after the register: the same flags in the same cycle, and the compares and the OR over the slots are not one
  // path from the answer (docs/fmax.md).
  private val checksReg = RegEnable(BvhNode.slotChecks(cfg, decoded.bits.body), decoded.valid)
  io.out.bits.node.errors := BvhNode.errors(checksReg)

  // Counted from registered handshakes (HeldCount): the request's handshake comes through the node port's
  // arbiter, and into the count's add it was the core control's longest path (docs/fmax.md).
  private val inMemory = HeldCount(Seq(io.mem.req.fire), Seq(io.mem.resp.fire), log2Ceil(cfg.numRayIds + 1))
  // A ray in a decode stage waits too (RtAccel's ray_conservation counts it here).
  private val decoding = if (BvhNode.staged(cfg)) recorded.valid +& decoded.valid else 0.U
  // The rays waiting, counted as they enter and leave for the output register (HeldCount): the sum of the parts'
  // counts into `waiting` was the unit's longest path (5.71 ns). The sum stays as an assertion.
  private val waiting = HeldCount(Seq(io.in.fire), Seq(decoded.valid), io.waiting.getWidth)
  assert(
    waiting === queue.io.count +& inMemory +& decoding,
    "prep_fetch_waiting: the rays counted into and out of PrepFetch differ from the sum of its parts"
  )
  io.waiting := waiting
}

object PrepFetch {

  /** Cycles from a node answer to `out`: the output register, and the two decode stages of the quantized layouts
    * (BvhNode.staged).
    */
  def latency(cfg: AccelConfig): Int = if (BvhNode.staged(cfg)) 3 else 1

  /** Node requests are tagged with the ray ID; one request brings one whole node record. */
  def port(cfg: AccelConfig): MemPortParams = MemPortParams(cfg.addrBits, cfg.rayIdBits, cfg.layout.nodeBytes)

  /** Byte offset of node `idx`: a shift for power-of-two node sizes, a
    * constant multiply (shifts and one add) for the 80-byte 8q node.
    */
  def nodeOffset(cfg: AccelConfig, idx: UInt): UInt = {
    val n = cfg.layout.nodeBytes
    if (isPow2(n)) idx << log2Ceil(n) else idx * n.U
  }
}

/** A ray's token with the node it fetched. */
class FetchedNode(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)
  val node = new BvhNode(cfg)
}
