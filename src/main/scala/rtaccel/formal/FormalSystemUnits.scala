package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.HitOut
import rtaccel.leaf.LeafIntersect
import rtaccel.system.{HitDma, ReadEngine, ReadReq, RayDma, SceneLoader, SystemConfig, WriteRecord}
import rtaccel.traversal.PrepFetch

/** The system units' environment, from how SystemCore drives them (docs/formal.md, "System units").
  * @param memLatency RayDma's memory answers a block 1..memLatency cycles after taking it (FormalMemEnv)
  * @param stall      a memory, the AXI slave (AR) or the writer refuses at most this many cycles in a row
  * @param takeStall  a consumer (the core taking rays, a read client taking records) refuses at most this many cycles in a row
  * @param readLatency, bursts the AXI slave's (FormalAxiReadSlave) for ReadEngine
  */
final case class UnitEnv(memLatency: Int, stall: Int, takeStall: Int, readLatency: Int, bursts: Int)

/** Each system unit's bounded response, derived term by term (docs/formal.md, "System units"), never chosen. */
object SystemUnitBound {

  /** RayDma, from the cycle after START to the last ray handed out, for `rays` rays in `blocks` <= rayBlockTags blocks:
    * START latched 1; each block request taken within S + 1 (no tag waits: blocks <= tags); the last answer L;
    * the block queue 1; then each ray one after the other, each refused at most H times: H + 1; the monitor 1.
    * Sequential, so loose: hand-out overlaps the reads. */
  def rayDma(sys: SystemConfig, e: UnitEnv, rays: Int): Int = {
    val blocks = (rays + sys.raysPerBlock - 1) / sys.raysPerBlock
    require(
      blocks <= sys.rayBlockTags,
      "SystemUnitBound.rayDma: more blocks than tags (a request would wait for a tag)"
    )
    1 + blocks * (e.stall + 1) + e.memLatency + 1 + rays * (e.takeStall + 1) + 1
  }

  /** The writer refuses a record at most S + 1 cycles in a row: its AW and W queues' heads leave within S + 1. */
  def writeStall(e: UnitEnv): Int = e.stall + 1

  /** HitDma, the batch's last hit taken -> every record handed to the writer (a hit may wait in the pair buffer
    * for its neighbour until then): the input slice's hits (<= 2, a line each at most), the decision stage's (1),
    * the hit queue's lines (FIFO, <= hitQueue - 1 ahead) and the pair buffer's flush, a scan of one slot a cycle,
    * each slot's line leaving within W + 1 (W: writeStall); the slice's register 1; the decision stage's 1; the
    * queue's register 1; the all-taken register 1 (the flush starts a cycle after the last hit is counted); the
    * scan's read register 1; the flush's stage 1; the monitor 1. */
  def hitDma(sys: SystemConfig, e: UnitEnv): Int =
    (HitDma.InSlice + 1 + sys.hitQueue + sys.pairSlots) * (writeStall(e) + 1) + 7

  /** HitDma takes a hit offered within W + 1 cycles (a full queue's head leaves by then, the input slice's head
    * into it the cycle after) + 1 (the slice's room shows the cycle after its head leaves) + 1 + 1. */
  def hitTake(e: UnitEnv): Int = writeStall(e) + 4

  /** ReadEngine, a request taken -> its record taken by the client:
    *  AR register 1, AR refusals S (the slave never fills: one burst per record, records <= slots <= bursts);
    *  the burst overdue after L; then at most every beat of every record outstanding, one per cycle (slots x maxBeats);
    *  R stage, completion queue and head queue 3; <= slots grants (ours and the records ahead), each waiting for
    *  its client's credit at most H + 2 (the client takes a record within H + 1, the credit frees the cycle after);
    *  select and read registers 2; the output queue, <= OutDepth - 1 records ahead and its own, each H + 1;
    *  the monitor 1. */
  def readEngine(maxBeats: Int, slots: Int, e: UnitEnv): Int =
    1 + e.stall + e.readLatency + slots * maxBeats + 3 + slots * (e.takeStall + 2) + 2 + ReadEngine.OutDepth * (e.takeStall + 1) + 1
}

/** Picks the batch once (START at a cycle of the environment's choice) with SystemCore's rules: a 64-aligned
  * buffer of `bufBytes` inside the address space, 1..maxRays rays. */
class BatchChoice(addrBits: Int, bufBytes: Int, maxRays: Int) {
  val startedReg = RegInit(false.B)
  val start = FormalAnySeq(Bool()) && !startedReg
  val base = FormalAnySeq(UInt(addrBits.W))
  val count = FormalAnySeq(UInt(4.W))
  val baseReg = Reg(UInt(addrBits.W))
  val countReg = RegInit(0.U(4.W))
  assume(
    !start || (base(5, 0) === 0.U && base <= ((1 << addrBits) - bufBytes).U && count >= 1.U && count <= maxRays.U),
    "batch_env: an aligned buffer inside the address space, 1..maxRays rays"
  )
  when(start) { startedReg := true.B; baseReg := base; countReg := count }
  private val ageReg = RegInit(0.U(8.W))
  when(startedReg && ageReg =/= 255.U) { ageReg := ageReg + 1.U }

  /** Cycles since the cycle after START. */
  val age: UInt = ageReg
}

/** A ready that refuses at most `n` cycles in a row. */
object TakeWithin {
  def apply(valid: Bool, n: Int): Bool = {
    val refusedReg = RegInit(0.U(log2Ceil(n + 1).max(1).W))
    val ready = if (n == 0) true.B else !FormalAnySeq(Bool()) || refusedReg === n.U
    when(valid && !ready) { refusedReg := refusedReg + 1.U }.otherwise { refusedReg := 0.U }
    ready
  }
}

/** RayDma alone: START once (RAY_BASE, RAY_COUNT free within the register map's rules), the ray blocks from a
  * memory answering within L in any order (FormalMemEnv), the core taking a ray after at most H refusals.
  * Asserted: each request reads a block of the batch, once (`raydma_read_once`); each ray handed out is in the
  * batch (`raydma_in_batch`, the premise of HitDma's `hit_in_batch`), once (`raydma_once`), after its block
  * came (`raydma_after_block`); all rays out within SystemUnitBound.rayDma (`raydma_bounded_response`).
  */
class FormalRayDmaTop(sys: SystemConfig, e: UnitEnv, maxRays: Int, name: String) extends Module {
  override def desiredName = s"FormalTop_$name"
  val io = IO(new Bundle {})
  private val rpb = sys.raysPerBlock
  private val maxBlocks = (maxRays + rpb - 1) / rpb
  private val dut = Module(new RayDma(sys))
  private val mem = Module(new FormalMemEnv(dut.io.mem.p, e.memLatency, e.stall))
  mem.io.mem <> dut.io.mem
  private val batch = new BatchChoice(sys.axiAddrBits, maxBlocks * sys.rayBlockBytes, maxRays)
  dut.io.start := batch.start
  dut.io.rayBase := batch.base
  dut.io.rayCount := batch.count
  // The unit's proofs are of a batch run to its end; a stopped batch is the system's (docs/faults.md).
  dut.io.stop := false.B
  dut.io.rays.ready := TakeWithin(dut.io.rays.valid, e.takeStall)
  private val count = batch.countReg
  private val blocks = (count +& (rpb - 1).U) >> log2Ceil(rpb)

  private val kBits = log2Ceil(maxBlocks + 1)
  private val req = dut.io.mem.req
  private val k = PriorityMux((0 until maxBlocks).map(j =>
    (req.bits.addr === batch.baseReg + (j * sys.rayBlockBytes).U && j.U < blocks) -> j.U(kBits.W)
  ) :+
    (true.B -> maxBlocks.U(kBits.W)))
  private val readRegs = RegInit(VecInit(Seq.fill(maxBlocks + 1)(false.B)))
  private val blockOfTagReg = Reg(Vec(sys.rayBlockTags, UInt(kBits.W)))
  private val cameRegs = RegInit(VecInit(Seq.fill(maxBlocks + 1)(false.B)))
  assert(
    !req.fire || (k =/= maxBlocks.U && !readRegs(k)),
    "raydma_read_once: a request for no block of the batch, or a block read twice"
  )
  when(req.fire) { readRegs(k) := true.B; blockOfTagReg(req.bits.tag) := k }
  when(dut.io.mem.resp.fire) { cameRegs(blockOfTagReg(dut.io.mem.resp.bits.tag)) := true.B }

  private val outRegs = RegInit(VecInit(Seq.fill(maxRays)(false.B)))
  private val number = dut.io.rays.bits.number
  private val idx = number(log2Ceil(maxRays) - 1, 0)
  private val ray = dut.io.rays
  assert(!ray.fire || number < count, "raydma_in_batch: a ray handed out whose number is not in the batch")
  assert(!(ray.fire && number < count) || !outRegs(idx), "raydma_once: a ray handed out twice")
  assert(
    !(ray.fire && number < count) || cameRegs(idx >> log2Ceil(rpb)),
    "raydma_after_block: a ray handed out before its block came"
  )
  when(ray.fire && number < count) { outRegs(idx) := true.B }
  private val all = VecInit((0 until maxRays).map(i => outRegs(i) || i.U >= count)).asUInt.andR
  private val limit = MuxLookup(count, 0.U)((1 to maxRays).map(r => r.U -> SystemUnitBound.rayDma(sys, e, r).U(8.W)))
  assert(
    !(batch.startedReg && !all && batch.age >= limit),
    "raydma_bounded_response: a ray of the batch not handed out within the derived bound"
  )
  assert(!dut.io.broken, "raydma_not_broken: RayDma's sticky broken rose")
}

/** HitDma alone: START once (HIT_BASE, RAY_COUNT free within the rules); after START the core offers hits, each
  * number in the batch (RayDma's `raydma_in_batch`) and at most once (the core's exactly-once), every other field
  * free; the writer refuses a record at most W cycles in a row (SystemUnitBound.writeStall).
  * Asserted: `hit_in_batch` (HitDma's own); each record written (alone or with its neighbour in one line) at
  * HIT_BASE + 32 n for a hit n taken and not yet written (`hitdma_once`); an offered hit taken within hitTake
  * (`hitdma_take`); once the batch's last hit is taken, every record handed to the writer within
  * SystemUnitBound.hitDma (`hitdma_bounded_response`; before that a hit may wait for its neighbour).
  */
class FormalHitDmaTop(sys: SystemConfig, e: UnitEnv, maxRays: Int, name: String) extends Module {
  override def desiredName = s"FormalTop_$name"
  val io = IO(new Bundle {})
  require(sys.cores == 1, "FormalHitDmaTop: one core")
  private val dut = Module(new HitDma(sys))
  private val batch = new BatchChoice(sys.axiAddrBits, maxRays * SystemConfig.HitBytes, maxRays)
  dut.io.start := batch.start
  dut.io.hitBase := batch.base
  dut.io.rayCount := batch.count
  // Whole batches only: no formal host here or in FormalSystem stops a batch; the stopped batch's flush is checked
  // in simulation (HitDmaSpec's stopped batches, SystemFaultsSpec).
  dut.io.stop := false.B; dut.io.issued := 0.U
  private val hit = dut.io.hits(0)
  private val takenRegs = RegInit(VecInit(Seq.fill(maxRays)(false.B)))
  hit.valid := FormalAnySeq(Bool()) && batch.startedReg
  hit.bits := FormalAnySeq(new HitOut(sys.core))
  private val n = hit.bits.number
  assume(
    !hit.valid || (n < batch.countReg && !takenRegs(n(log2Ceil(maxRays) - 1, 0))),
    "hitdma_env: a hit of the batch, each number once"
  )
  private val w = dut.io.write
  w.ready := TakeWithin(w.valid, SystemUnitBound.writeStall(e))

  private val bound = SystemUnitBound.hitDma(sys, e)
  private val pendingRegs = RegInit(VecInit(Seq.fill(maxRays)(false.B)))
  private val ageRegs = RegInit(VecInit(Seq.fill(maxRays)(0.U(log2Ceil(bound + 2).W))))
  private val offset = w.bits.addr - batch.baseReg
  // Record k of a line: (line - HIT_BASE) / 32 + k, written when its half's bit is set.
  private val first = offset(w.bits.addr.getWidth - 1, log2Ceil(SystemConfig.HitBytes))
  private val halves = (0 until WriteRecord.Records).map(k => w.bits.halves(k))
  private val index = halves.indices.map(k => first + k.U)
  private val ok =
    w.bits.addr >= batch.baseReg && offset(log2Ceil(WriteRecord.Bytes) - 1, 0) === 0.U && halves.reduce(_ || _) &&
      halves.zip(index).map { case (on, i) => !on || i < batch.countReg }.reduce(_ && _)
  private val wi = index.map(_(log2Ceil(maxRays) - 1, 0))
  assert(
    !w.fire || (ok && halves.zip(wi).map { case (on, i) => !on || pendingRegs(i) }.reduce(_ && _)),
    "hitdma_once: a record written for no hit taken and waiting"
  )
  private val allTaken = VecInit((0 until maxRays).map(i => takenRegs(i) || i.U >= batch.countReg)).asUInt.andR
  for (i <- 0 until maxRays) {
    val in = hit.fire && n === i.U
    val out = w.fire && ok && halves.zip(wi).map { case (on, j) => on && j === i.U }.reduce(_ || _)
    when(in) { takenRegs(i) := true.B; pendingRegs(i) := true.B; ageRegs(i) := 0.U }
    when(out) { pendingRegs(i) := false.B }
    // The age runs once the batch's last hit is taken: until then a record may wait for its neighbour.
    when(pendingRegs(i) && !out && allTaken && ageRegs(i) <= bound.U) { ageRegs(i) := ageRegs(i) + 1.U }
    assert(
      !pendingRegs(i) || ageRegs(i) < bound.U,
      s"hitdma_bounded_response: hit $i's record not handed to the writer within $bound cycles of the batch's last hit"
    )
  }
  private val waitReg = RegInit(0.U(4.W))
  waitReg := Mux(hit.valid && !hit.ready, waitReg + 1.U, 0.U)
  assert(waitReg < SystemUnitBound.hitTake(e).U, "hitdma_take: a hit offered and not taken within the derived bound")
}

/** ReadEngine alone, with SystemCore's read clients (the core's node and triangle ports, the scene loader, RayDma:
  * their record sizes and tag widths) and the formal AXI slave (FormalAxiReadSlave, its AR straight to the engine's):
  * each client asks for any record (any address, but no record crossing a 4 KB page: one burst per record; a
  * crossing record's two bursts are not covered, docs/formal.md) with any tag of its width not already waiting; the core's clients refuse a record at most H cycles in a
  * row, the loader and RayDma always take it. Asserted: the engine's own assertions; each record answered to its
  * client with its tag, once (`read_answer_once`), within SystemUnitBound.readEngine (`read_bounded_response`);
  * the engine never flags an error (`read_no_error`: no beat for no record, every rlast where it belongs).
  */
class FormalReadEngineTop(sys: SystemConfig, e: UnitEnv, name: String) extends Module {
  override def desiredName = s"FormalTop_$name"
  val io = IO(new Bundle {})
  private val ports = FormalReadEngineTop.ports(sys)
  private val refuses = Seq(true, true, false, false)
  private val tagBits = ports.map(_.tagBits).max
  private val slots = FormalReadEngineTop.slots(sys)
  private val dut = Module(new ReadEngine(sys.axi, ports.map(_.recordBytes), tagBits, slots))
  private val slave = Module(new FormalAxiReadSlave(sys.axi, e.readLatency, e.stall, e.bursts))
  require(slots <= e.bursts, "FormalReadEngineTop: one burst per record and no more records than the slave holds")
  slave.io.ar <> dut.io.ar
  dut.io.r.valid := slave.io.r.valid
  dut.io.r.bits := slave.io.r.bits
  slave.io.r.ready := true.B
  slave.io.data := FormalAnySeq(UInt(sys.axiDataBits.W))
  private val bound = SystemUnitBound.readEngine(FormalReadEngineTop.maxBeats(sys), slots, e)

  private val n = ports.size
  private val keys = n << tagBits
  private val waitRegs = RegInit(VecInit(Seq.fill(keys)(false.B)))
  private val ageRegs = RegInit(VecInit(Seq.fill(keys)(0.U(log2Ceil(bound + 2).W))))
  private val req = dut.io.req
  req.valid := FormalAnySeq(Bool())
  req.bits := FormalAnySeq(new ReadReq(sys.axiAddrBits, log2Ceil(n), tagBits))
  private val bytes = MuxLookup(req.bits.client, 0.U)(ports.zipWithIndex.map { case (p, c) =>
    c.U -> p.recordBytes.U(13.W)
  })
  private val tagOk = MuxLookup(req.bits.client, false.B)(ports.zipWithIndex.map { case (p, c) =>
    c.U -> (req.bits.tag >> p.tagBits === 0.U)
  })
  private val pageEnd = req.bits.addr(11, 0) +& bytes
  assume(
    !req.valid || (req.bits.client < n.U && tagOk && pageEnd <= 4096.U && !waitRegs(Cat(
      req.bits.client,
      req.bits.tag
    ))),
    "read_env: a client's record, its tag free, inside one 4 KB page"
  )
  for (i <- 0 until keys) {
    val c = i >> tagBits
    val t = i & ((1 << tagBits) - 1)
    val in = req.fire && req.bits.client === c.U && req.bits.tag === t.U
    val out = dut.io.resp(c).fire && dut.io.resp(c).bits.tag === t.U
    when(in) { waitRegs(i) := true.B; ageRegs(i) := 0.U }
    when(out) { waitRegs(i) := false.B }
    when(waitRegs(i) && !out && ageRegs(i) <= bound.U) { ageRegs(i) := ageRegs(i) + 1.U }
    assert(!waitRegs(i) || ageRegs(i) < bound.U, s"read_bounded_response: client $c tag $t waits $bound cycles")
  }
  for (c <- 0 until n) {
    val r = dut.io.resp(c)
    r.ready := (if (refuses(c)) TakeWithin(r.valid, e.takeStall) else true.B)
    assert(
      !r.fire || waitRegs(Cat(c.U(log2Ceil(n).W), r.bits.tag)),
      s"read_answer_once: client $c got a record for no waiting request"
    )
  }
  assert(!dut.io.error, "read_no_error: the engine flagged an error against a well-behaved slave")
}

object FormalReadEngineTop {

  /** SystemCore's read clients, in MemoryFabric's order: the core's node port (PrepFetch's and the traversal's
    * requests, one tag bit says whose), its triangle port, the scene loader, RayDma. */
  def ports(sys: SystemConfig): Seq[rtaccel.mem.MemPortParams] = {
    val cfg = sys.core
    Seq(
      PrepFetch.port(cfg).copy(tagBits = PrepFetch.port(cfg).tagBits + 1),
      LeafIntersect.port(cfg),
      SceneLoader.port(sys),
      RayDma.port(sys)
    )
  }

  /** MemoryFabric's read slots: every AXI ID but the store fill's. */
  def slots(sys: SystemConfig): Int = (1 << sys.axi.idBits) - 1

  /** Beats of the largest record at its worst alignment (as ReadEngine counts them). */
  def maxBeats(sys: SystemConfig): Int = {
    val b = sys.axi.beatBytes
    ports(sys).map(p => (b + p.recordBytes - 2) / b + 1).max
  }
}
