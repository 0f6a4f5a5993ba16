package rtaccel.fetch

import chisel3._
import chisel3.util._
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.traversal.PrepFetch
import rtaccel.{AccelConfig, Datapath, HeldCount, RayIdFreeList}
import rtaccel.bvh.BvhNode

/** A ray with its ID, out of RayPrep. */
class PreparedEntry[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val rayId = UInt(cfg.rayIdBits.W)
  val shadow = Bool()
  val ray = new PreparedRay(cfg, gen)
}

/** Where rays come in.
  *
  *  - Each ray takes an ID from the free list (so at most `numRayIds` rays are
  *    ever inside); its host number is kept by ID for the output stage.
  *  - RayPrep computes its constants once; the prepared ray goes on to
  *    InitTraversal, `prepared` being a valid pipe that cannot wait.
  *  - The root node is fetched once, after reset and whenever `nodeBase`
  *    changes, and kept on chip (`root`): new rays never use the node port,
  *    fixing the seed's per-ray root fetch that competed with traversal. Rays
  *    wait until the root has arrived.
  */
class FetchBVH[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val port: MemPortParams = PrepFetch.port(cfg)
  val io = IO(new Bundle {
    val rays = Flipped(Decoupled(new RayIn))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem = new MemPort(port)
    val prepared = Valid(new PreparedEntry(cfg, dp.gen))

    /** The on-chip root, valid whenever a ray can have entered. */
    val root = Output(new BvhNode(cfg))

    /** A ray took this ID: LeafIntersect forgets the ID's previous hit. */
    val started = Valid(UInt(cfg.rayIdBits.W))

    /** IDs coming back from the output stage. */
    val free = Flipped(Decoupled(UInt(cfg.rayIdBits.W)))

    /** Host ray number of an ID, read by the output stage. */
    val numberId = Input(UInt(cfg.rayIdBits.W))
    val number = Output(UInt(32.W))
    val inFlight = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))

    /** Rays this unit holds now (RtAccel's ray_conservation assertion). */
    val held = Output(UInt(log2Ceil(cfg.numRayIds + 1).W))

    /** Sticky: an ID was freed twice (a lost-or-duplicated-ray bug). */
    val doubleFree = Output(Bool())
  })
  override def desiredName = s"FetchBVH_k${cfg.boxLanes}_n${cfg.numRayIds}"

  // ---- Root node, fetched once per scene base ----
  // Requests carry a generation number, so a late answer for an old base is
  // never taken for the new root.
  private val rootReg = Reg(new BvhNode(cfg))
  private val rootChecksReg = Reg(Vec(cfg.boxLanes, new BvhNode.SlotChecks))
  private val rootValidReg = RegInit(false.B)
  private val rootAskedReg = RegInit(false.B)
  private val baseReg = RegInit(0.U(cfg.addrBits.W))
  private val genReg = RegInit(0.U(cfg.rayIdBits.W))
  private val baseChanged = io.nodeBase =/= baseReg
  // The root's request leaves from a one-entry queue, so the base's compare does not run through the node
  // port's arbiter into PrepFetch (docs/fmax.md): a cycle more per root fetch. A request still queued when the
  // base changes is dropped in that cycle (it is offered in it, so a user that must never see the old base's
  // request holds the port for a cycle after a change: SystemCore), and the new root is asked for.
  private val rootReq = Wire(Decoupled(chiselTypeOf(io.mem.req.bits)))
  rootReq.valid := !rootAskedReg && !baseChanged
  rootReq.bits.addr := baseReg
  rootReq.bits.tag := genReg
  io.mem.req <> Queue(rootReq, 1, flush = Some(baseChanged))
  when(rootReq.fire) { rootAskedReg := true.B }
  when(baseChanged) {
    baseReg := io.nodeBase
    genReg := genReg + 1.U
    rootValidReg := false.B
    rootAskedReg := false.B
  }
  io.mem.resp.ready := true.B
  if (BvhNode.staged(cfg)) {
    // The record with its slots' counts, then its words, are registered before the checks, as in PrepFetch
    // (BvhNode.staged): the root is valid two cycles after its answer. A base change in either cycle drops it (the
    // new base's root is fetched afresh).
    val rootAnswer = io.mem.resp.fire && io.mem.resp.bits.tag === genReg && !baseChanged
    val rootRecordReg = RegEnable(BvhNode.record(cfg, io.mem.resp.bits.data), rootAnswer)
    val rootRecordedReg = RegNext(rootAnswer, false.B)
    val rootWordsReg = RegEnable(BvhNode.words(cfg, rootRecordReg), rootRecordedReg)
    val rootDecodeReg = RegNext(rootRecordedReg && !baseChanged, false.B)
    when(rootDecodeReg && !baseChanged) {
      rootReg := BvhNode.fields(cfg, rootWordsReg)
      rootChecksReg := BvhNode.slotChecks(cfg, rootWordsReg)
      rootValidReg := true.B
    }
  } else when(io.mem.resp.fire && io.mem.resp.bits.tag === genReg && !baseChanged) {
    val words = BvhNode.words(cfg, io.mem.resp.bits.data)
    rootReg := BvhNode.fields(cfg, words)
    rootChecksReg := BvhNode.slotChecks(cfg, words)
    rootValidReg := true.B
  }
  // The slots' checks are registered with the root and combined after the register, as in PrepFetch.
  io.root := rootReg
  io.root.errors := BvhNode.errors(rootChecksReg)

  // ---- IDs and ray constants ----
  // A free takes effect a cycle later (RayIdFreeList's `lateCheck`): RtAccel counts the ray as held meanwhile.
  private val ids = Module(new RayIdFreeList(cfg.numRayIds, lateCheck = true))
  ids.io.free <> io.free
  io.inFlight := ids.io.inFlight
  io.doubleFree := ids.io.doubleFree

  private val numbers = Mem(cfg.numRayIds, UInt(32.W))
  io.number := numbers.read(io.numberId)

  io.rays.ready := ids.io.alloc.valid && rootValidReg
  ids.io.alloc.ready := io.rays.valid && rootValidReg
  private val id = ids.io.alloc.bits
  when(io.rays.fire) { numbers.write(id, io.rays.bits.number) }
  io.started.valid := io.rays.fire
  io.started.bits := id

  private val prep = Module(dp.rayPrep(cfg))
  prep.io.in.valid := io.rays.fire
  prep.io.in.bits := io.rays.bits.ray
  class Carry extends Bundle {
    val rayId = UInt(cfg.rayIdBits.W)
    val shadow = Bool()
  }
  private val carryIn = Wire(new Carry)
  carryIn.rayId := id
  carryIn.shadow := io.rays.bits.shadow
  private val carry = Pipe(io.rays.fire, carryIn, prep.latency)
  // The rays in RayPrep, counted as they enter and leave it. A popcount of the carry pipe's valid stages
  // would be the unit's longest path (6.71 ns, docs/fmax.md), for a count only assertions read; the
  // handshakes are registered before they are added (HeldCount), so no valid reaches the add in its own cycle.
  // The popcount stays as an assertion (simulation and formal only).
  private val held = HeldCount(Seq(io.rays.fire), Seq(carry.valid), log2Ceil(prep.latency + 1))
  assert(
    held === PopCount(ShiftRegisters(io.rays.fire, prep.latency, false.B, true.B)),
    "fetch_held_count: the rays counted into and out of RayPrep differ from the carry pipe's valid stages"
  )
  io.held := held
  io.prepared.valid := prep.io.out.valid
  io.prepared.bits.rayId := carry.bits.rayId
  io.prepared.bits.shadow := carry.bits.shadow
  io.prepared.bits.ray := prep.io.out.bits
}
