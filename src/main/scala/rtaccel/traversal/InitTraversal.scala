package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.fetch.PreparedEntry
import rtaccel.AccelConfig
import rtaccel.bvh.BvhNode
import rtaccel.system.RamQueue

/** A new ray, at the root, with the root node it will be tested against. */
class EntryToken(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)
  val root = new BvhNode(cfg)
}

/** The ray's entry into traversal: a prepared ray (with its ID) is written to
  * the RayBuffer, and only then handed to the box stage as a token at the
  * root (`nodeIdx = 0`, empty stack) carrying the on-chip root node, so its
  * first box test reads what was written.
  *
  * Prepared rays arrive on a valid pipe and wait in a queue of `numRayIds`
  * entries: every ray inside holds an ID, so at most `numRayIds` can ever be
  * waiting and the queue cannot overflow. One ray can enter per cycle. The enqueue is checked all the
  * same: `broken` would latch if it ever found the queue full.
  */
class InitTraversal[T <: Data](cfg: AccelConfig, gen: T) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(Valid(new PreparedEntry(cfg, gen)))
    val root = Input(new BvhNode(cfg))
    val enter = Decoupled(new RayEntry(cfg, gen))
    val out = Decoupled(new EntryToken(cfg))

    /** Sticky: a prepared ray found the queue full (a lost ray; cannot happen). */
    val broken = Output(Bool())

    /** Rays this unit holds now (RtAccel's ray_conservation assertion). */
    val held = Output(UInt(log2Ceil(cfg.numRayIds + 7).W))
  })
  override def desiredName = s"InitTraversal_k${cfg.boxLanes}_n${cfg.numRayIds}"

  private val waiting = Module(new RamQueue(new PreparedEntry(cfg, gen), cfg.numRayIds))
  waiting.io.enq.valid := io.in.valid
  waiting.io.enq.bits := io.in.bits
  private val brokenReg = RegInit(false.B)
  when(io.in.valid && !waiting.io.enq.ready) { brokenReg := true.B }
  io.broken := brokenReg

  // First the RayBuffer write, then, from the next cycle on, the hand-over:
  // the box stage reads the RayBuffer in the very cycle it takes a ray, and a
  // read in the cycle of the write would see the old entry. A two-entry
  // queue of written rays lets the next ray be written while the previous
  // one is handed over, so a ray can enter every cycle. (enter.valid depends
  // on the queue's state, never on a ready from outside.)
  // The queue's head is a register (RamQueue): the hand-over's handshake ends there. Taken from a chisel3.util
  // Queue in block RAM, its pointers ran through the empty compare and the handshake into its read address
  // (5.53 ns, docs/fmax.md).
  private val next = waiting.io.deq
  private val head = next.bits
  private val written = Module(new Queue(new TraversalToken(cfg), 2)) // the token only: the rest is in the RayBuffer
  io.enter.valid := next.valid && written.io.enq.ready
  io.enter.bits.rayId := head.rayId
  io.enter.bits.statics := head.ray.statics
  io.enter.bits.tmax := head.ray.tmax
  next.ready := io.enter.ready && written.io.enq.ready
  written.io.enq.valid := io.enter.fire
  private val t = written.io.enq.bits
  t.rayId := head.rayId
  t.nodeIdx := 0.U
  t.sp := 0.U
  t.dirNeg := head.ray.dirNeg
  t.shadow := head.shadow
  t.errors := head.ray.errors
  io.out.valid := written.io.deq.valid
  io.out.bits.token := written.io.deq.bits
  written.io.deq.ready := io.out.ready
  io.out.bits.root := io.root
  io.held := waiting.io.count +& written.io.count
}
