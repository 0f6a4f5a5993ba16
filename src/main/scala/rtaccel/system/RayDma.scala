package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.fetch.{RawRay, RayIn}
import rtaccel.mem.{MemPort, MemPortParams}

/** Reads the batch's ray records (48 bytes each, docs/reports/register-map.md) in
  * blocks of `raysPerBlock` (whole 64-byte lines from a 64-aligned RAY_BASE),
  * up to `rayBlockTags` blocks in flight, answered in any order, and hands the
  * rays out one per cycle. Rays leave in block-arrival order; RayIn.number is
  * the record's index, so order does not matter.
  *
  * Flags: bit 0 is shadow. A record with any other flag bit set is made an
  * invalid ray (its origin x becomes a quiet NaN), so the core returns it with
  * ErrorFlags.InvalidRay and no hit. Bytes 36..47 are not read.
  * The last block may read up to `rayBlockBytes - 48` bytes past the last record.
  */
class RayDma(sys: SystemConfig) extends Module {
  private val rpb = sys.raysPerBlock
  require(isPow2(rpb), s"RayDma: raysPerBlock must be a power of two, got $rpb")
  val io = IO(new Bundle {
    val start = Input(Bool())
    val rayBase = Input(UInt(sys.axiAddrBits.W))
    val rayCount = Input(UInt(32.W))
    val mem = new MemPort(RayDma.port(sys))
    val rays = Decoupled(new RayIn)

    /** Stop the batch (ABORT, a fault): no more block reads; blocks still
      * arriving are taken and dropped, their rays not handed out. */
    val stop = Input(Bool())

    /** No block read in flight and none buffered: after `stop`, no ray will come. */
    val idle = Output(Bool())

    /** Sticky: a block came back for a tag not in flight. */
    val broken = Output(Bool())
  })
  private val nTags = sys.rayBlockTags
  private val subBits = log2Ceil(rpb).max(1)
  private val issuedReg = RegInit(0.U(32.W))
  // Rays of the batch not yet covered by an issued block read: a block is read while any remain.
  private val remainingReg = RegInit(0.U(32.W))
  private val addrReg = RegInit(0.U(sys.axiAddrBits.W))
  private val freeReg = RegInit(((BigInt(1) << nTags) - 1).U(nTags.W))
  private val blockOfTag = Reg(Vec(nTags, UInt(32.W)))
  // Index of the block's last ray of the batch (rpb - 1 but in the batch's last block), fixed when the
  // block is read: the output side then steps through a block with no compare against RAY_COUNT,
  // which kept a 32-bit compare behind the tag mux on the dequeue path.
  private val lastSubOfTag = Reg(Vec(nTags, UInt(subBits.W)))
  private val brokenReg = RegInit(false.B)

  when(io.start) {
    remainingReg := io.rayCount
    issuedReg := 0.U
    addrReg := io.rayBase
  }
  private val tag = PriorityEncoder(freeReg)
  private val fullBlock = remainingReg >= rpb.U
  io.mem.req.valid := remainingReg =/= 0.U && freeReg.orR && !io.start && !io.stop
  io.mem.req.bits.addr := addrReg
  io.mem.req.bits.tag := tag
  when(io.mem.req.fire) {
    blockOfTag(tag) := issuedReg
    lastSubOfTag(tag) := Mux(fullBlock, (rpb - 1).U, remainingReg - 1.U)
    issuedReg := issuedReg + 1.U
    remainingReg := Mux(fullBlock, remainingReg - rpb.U, 0.U)
    addrReg := addrReg + sys.rayBlockBytes.U
  }

  // One buffer entry per tag: a block arrives only for a tag in flight, and its
  // tag is free again only when its entry leaves, so the queue never overflows.
  // An entry holds the block's rays as the output hands them out (origin x already made a quiet NaN for a record
  // with an unknown flag bit), the block's number and the index of its last ray of the batch, all formed as the
  // block arrives: the hand-out then reads a ray by `subReg` (a select of `raysPerBlock`), with no per-tag table,
  // flag test or shifter between the queue's read and the ray's fields (with them there, 5.53 ns, docs/fmax.md).
  private val q = Module(new Queue(
    new Bundle {
      val rays = Vec(rpb, new RayDma.Ray)
      val block = UInt(32.W)
      val lastSub = UInt(subBits.W)
      val tag = UInt(sys.rayTagBits.W)
    },
    nTags
  ))
  io.mem.resp.ready := true.B
  q.io.enq.valid := io.mem.resp.valid
  private val respTag = io.mem.resp.bits.tag
  for (k <- 0 until rpb) {
    val rec = io.mem.resp.bits.data(SystemConfig.RayBytes * 8 * (k + 1) - 1, SystemConfig.RayBytes * 8 * k)
    def word(j: Int): UInt = rec(32 * j + 31, 32 * j)
    val flags = word(8)
    val r = q.io.enq.bits.rays(k)
    r.ray.origin(0) := Mux(flags(31, 1) =/= 0.U, RayDma.QuietNaN.U(32.W), word(0))
    r.ray.origin(1) := word(1)
    r.ray.origin(2) := word(2)
    for (j <- 0 until 3) r.ray.dir(j) := word(3 + j)
    r.ray.tmin := word(6)
    r.ray.tmax := word(7)
    r.shadow := flags(0)
  }
  q.io.enq.bits.block := blockOfTag(respTag)
  q.io.enq.bits.lastSub := lastSubOfTag(respTag)
  q.io.enq.bits.tag := respTag
  when(io.mem.resp.valid && (!q.io.enq.ready || freeReg(respTag))) { brokenReg := true.B }
  assert(
    !(io.mem.resp.valid && (!q.io.enq.ready || freeReg(respTag))),
    "ray_block_once: a ray block came back for a tag not in flight, or found the block queue full"
  )

  // ---- unpack: ray `subReg` of the head block ----
  private val subReg = RegInit(0.U(subBits.W))
  private val head = q.io.deq.bits
  private val lastSub = head.lastSub
  // subReg runs from 0 to lastSub and no further, so every ray stepped through is in the batch.
  assert(!q.io.deq.valid || subReg <= lastSub, "ray_block_sub: RayDma stepped past its block's last ray")
  private val present = !io.stop
  private val ray = if (rpb == 1) head.rays(0) else head.rays(subReg)
  io.rays.bits.number := Cat(head.block, 0.U(log2Ceil(rpb).W)) | subReg
  io.rays.bits.ray := ray.ray
  io.rays.bits.shadow := ray.shadow
  io.rays.valid := q.io.deq.valid && present
  private val step = q.io.deq.valid && (io.rays.ready || !present)
  private val last = subReg === lastSub || !present
  q.io.deq.ready := step && last
  when(step) { subReg := Mux(last, 0.U, subReg + 1.U) }
  private val freed = Mux(q.io.deq.fire, UIntToOH(q.io.deq.bits.tag, nTags), 0.U)
  private val taken = Mux(io.mem.req.fire, UIntToOH(tag, nTags), 0.U)
  freeReg := (freeReg | freed) & ~taken
  io.broken := brokenReg
  io.idle := freeReg.andR
}

object RayDma {
  val QuietNaN = 0x7fc00000L

  /** A ray as handed out, less its number. */
  class Ray extends Bundle {
    val ray = new RawRay
    val shadow = Bool()
  }
  def port(sys: SystemConfig): MemPortParams = MemPortParams(sys.axiAddrBits, sys.rayTagBits, sys.rayBlockBytes)
}
