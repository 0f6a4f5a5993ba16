package rtaccel.fetch

import chisel3._
import chisel3.util._
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.traversal.{PrepFetch, RayEntry, TraversalToken}
import rtaccel.{AccelConfig, BvhNode, Datapath, RayIdFreeList}

/** A new ray, at the root, with the root node it will be tested against. */
class EntryToken(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)
  val root  = new BvhNode(cfg)
}

/** Where rays come in.
  *
  *  - Each ray takes an ID from the free list; its host number is kept by ID
  *    for the output stage.
  *  - RayPrep computes its constants once; the ray is written to the
  *    RayBuffer, and only then sent to the root, so its first box test reads
  *    what was written.
  *  - The root node is fetched once, after reset and whenever `nodeBase`
  *    changes, and kept on chip: new rays never use the node port, fixing
  *    the seed's per-ray root fetch that competed with traversal. Rays wait
  *    until the root has arrived.
  */
class FetchBVH[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val port: MemPortParams = PrepFetch.port(cfg)
  val io = IO(new Bundle {
    val rays     = Flipped(Decoupled(new RayIn))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem      = new MemPort(port)
    val enter    = Decoupled(new RayEntry(cfg, dp.gen))
    val out      = Decoupled(new EntryToken(cfg))
    /** A ray took this ID: LeafIntersect forgets the ID's previous hit. */
    val started  = Valid(UInt(cfg.rayIdBits.W))
    /** IDs coming back from the output stage. */
    val free     = Flipped(Decoupled(UInt(cfg.rayIdBits.W)))
    /** Host ray number of an ID, read by the output stage. */
    val numberId = Input(UInt(cfg.rayIdBits.W))
    val number   = Output(UInt(32.W))
    val inFlight = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))
    /** Sticky: an ID was freed twice (a lost-or-duplicated-ray bug). */
    val doubleFree = Output(Bool())
  })
  override def desiredName = s"FetchBVH_n${cfg.numRayIds}"

  // ---- Root node, fetched once per scene base ----
  // Requests carry a generation number, so a late answer for an old base is
  // never taken for the new root.
  private val rootReg      = Reg(new BvhNode(cfg))
  private val rootValidReg = RegInit(false.B)
  private val rootAskedReg = RegInit(false.B)
  private val baseReg      = RegInit(0.U(cfg.addrBits.W))
  private val genReg       = RegInit(0.U(cfg.rayIdBits.W))
  private val baseChanged  = io.nodeBase =/= baseReg
  when(baseChanged) {
    baseReg      := io.nodeBase
    genReg       := genReg + 1.U
    rootValidReg := false.B
    rootAskedReg := false.B
  }
  io.mem.req.valid     := !rootAskedReg && !baseChanged
  io.mem.req.bits.addr := baseReg
  io.mem.req.bits.tag  := genReg
  when(io.mem.req.fire) { rootAskedReg := true.B }
  io.mem.resp.ready := true.B
  when(io.mem.resp.fire && io.mem.resp.bits.tag === genReg && !baseChanged) {
    rootReg      := BvhNode.decode(cfg, io.mem.resp.bits.data)
    rootValidReg := true.B
  }

  // ---- IDs and ray constants ----
  private val ids = Module(new RayIdFreeList(cfg.numRayIds))
  ids.io.free <> io.free
  io.inFlight   := ids.io.inFlight
  io.doubleFree := ids.io.doubleFree

  private val numbers = Mem(cfg.numRayIds, UInt(32.W))
  io.number := numbers.read(io.numberId)

  io.rays.ready      := ids.io.alloc.valid && rootValidReg
  ids.io.alloc.ready := io.rays.valid && rootValidReg
  private val id = ids.io.alloc.bits
  when(io.rays.fire) { numbers.write(id, io.rays.bits.number) }
  io.started.valid := io.rays.fire
  io.started.bits  := id

  private val prep = Module(dp.rayPrep(cfg))
  prep.io.in.valid := io.rays.fire
  prep.io.in.bits  := io.rays.bits.ray
  class Carry extends Bundle {
    val rayId  = UInt(cfg.rayIdBits.W)
    val shadow = Bool()
  }
  private val carryIn = Wire(new Carry)
  carryIn.rayId  := id
  carryIn.shadow := io.rays.bits.shadow
  private val carry = Pipe(io.rays.fire, carryIn, prep.latency)

  // Prepared rays wait here; at most numRayIds rays exist, so it never overflows.
  class Prepared extends Bundle {
    val carry = new Carry
    val ray   = new PreparedRay(cfg, dp.gen)
  }
  private val ready = Module(new Queue(new Prepared, cfg.numRayIds))
  ready.io.enq.valid      := prep.io.out.valid
  ready.io.enq.bits.carry := carry.bits
  ready.io.enq.bits.ray   := prep.io.out.bits

  // First the RayBuffer write, then the ray goes to the root, so its first box
  // test reads what was written. (Valid never waits on ready: the RayBuffer's
  // round-robin arbiter would close a combinational loop.)
  private val head       = ready.io.deq.bits
  private val enteredReg = RegInit(false.B)
  io.enter.valid        := ready.io.deq.valid && !enteredReg
  io.enter.bits.rayId   := head.carry.rayId
  io.enter.bits.statics := head.ray.statics
  io.enter.bits.tmax    := head.ray.tmax
  when(io.enter.fire) { enteredReg := true.B }
  io.out.valid          := ready.io.deq.valid && enteredReg
  ready.io.deq.ready    := io.out.ready && enteredReg
  when(io.out.fire) { enteredReg := false.B }

  private val t = io.out.bits.token
  t.rayId   := head.carry.rayId
  t.nodeIdx := 0.U
  t.sp      := 0.U
  t.dirNeg  := head.ray.dirNeg
  t.shadow  := head.carry.shadow
  t.errors  := head.ray.errors
  io.out.bits.root := rootReg
}
