package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayIn
import rtaccel.fp.FloatFormat
import rtaccel.axi.Axi4
import rtaccel.leaf.LeafIntersect
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.scene.MemoryImage
import rtaccel.system.{RegisterMap, SystemConfig, SystemCore}
import rtaccel.traversal.PrepFetch
import rtaccel.{AccelConfig, HitOut, PerfCounters, RtAccel}
import rtaccel.bvh.BvhLayout

/** The system's formal environment (docs/formal.md, "System level").
  *
  * @param readLatency  an AXI read burst older than this many cycles takes the R channel (any overdue one)
  * @param stall        the slave refuses AR, AW or W at most this many cycles in a row; the core stub refuses a memory answer at most this many
  * @param bLatency     a written beat's B response comes after at most this many refusals in a row
  * @param maxRays      the batch holds 1..maxRays rays (the environment chooses)
  * @param bursts       read bursts the slave holds at once (it refuses AR when full)
  */
final case class SystemEnv(readLatency: Int, stall: Int, bLatency: Int, maxRays: Int, bursts: Int)

/** One system proof: the configuration, environment and depth. `window`: the host first sets a DMA window of
  * its choice (WINDOW_BASE, WINDOW_LIMIT, free), and the case checks `window_kept` instead of the batch's
  * end-to-end properties (a refused burst stops the batch, so DONE no longer means every ray). */
final case class SystemCase(name: String, sys: SystemConfig, env: SystemEnv, depth: Int, window: Boolean = false)

object SystemCase {

  /** 1 core of 2 ray IDs, 12-bit addresses (the AXI minimum), 2 AXI ID bits (3 read slots + the store's fill),
    * a 64-byte node store (one node), no triangle store, 2 ray blocks in flight, a 2-deep hit queue, 2 pair slots. */
  val sys2: SystemConfig = {
    val core = AccelConfig(
      numRayIds = 2,
      stackDepth = 2,
      maxNodes = 2,
      maxTriangles = 2,
      maxLeafSize = 2,
      boxFloat = FloatFormat(3, 2),
      triFloat = FloatFormat(3, 2),
      addrBits = 12,
      layout = BvhLayout.Wide(2)
    )
    SystemConfig(
      core = core,
      cores = 1,
      axiDataBits = 512,
      axiAddrBits = 12,
      axiIdBits = 2,
      nodeStoreBytes = 64,
      triStoreBytes = 0,
      raysPerBlock = 4,
      rayBlockTags = 2,
      hitQueue = 2,
      hitPairSlots = 2
    )
  }
  val env: SystemEnv = SystemEnv(readLatency = 3, stall = 1, bLatency = 2, maxRays = 8, bursts = 4)

  /** w1's depth: the two window writes, LOAD_SCENE, the header read, the fills, the batch's registers, START and
    * the first ray block and core reads (docs/formal.md, "System level"). */
  val all: Seq[SystemCase] =
    Seq(SystemCase("s1", sys2, env, depth = 42), SystemCase("w1", sys2, env, depth = 30, window = true))

  /** The units' environment, from s1's: memory and AXI slave as env (L = 3, S = 1, 4 bursts), the core and
    * the read clients refusing at most env.stall = 1 cycle in a row. */
  val unitEnv: UnitEnv = UnitEnv(
    memLatency = env.readLatency,
    stall = env.stall,
    takeStall = env.stall,
    readLatency = env.readLatency,
    bursts = env.bursts
  )

  /** Each system unit alone (FormalSystemUnits), in s1's configuration, checked by BMC 8 steps past its bound. */
  val units: Seq[UnitCase] = {
    val e = unitEnv
    val rays = env.maxRays
    val rd = SystemUnitBound.rayDma(sys2, e, rays)
    val hd = SystemUnitBound.hitDma(sys2, e)
    val beats = FormalReadEngineTop.maxBeats(sys2)
    val re = SystemUnitBound.readEngine(beats, FormalReadEngineTop.slots(sys2), e)
    Seq(
      UnitCase(
        "raydma",
        () => new FormalRayDmaTop(sys2, e, rays, "raydma"),
        rd,
        rd + 8,
        deep = true,
        terms = (1 to rays).map(r => s"$r rays: ${SystemUnitBound.rayDma(sys2, e, r)}").mkString(", ")
      ),
      UnitCase(
        "hitdma",
        () => new FormalHitDmaTop(sys2, e, rays, "hitdma"),
        hd,
        hd + 8,
        deep = true,
        terms =
          s"after the batch's last hit: (hit queue ${sys2.hitQueue} + pair slots ${sys2.hitPairSlots}) x (writer refusals ${SystemUnitBound.writeStall(e)} + 1) + 2"
      ),
      // bmc3's frames on this harness double from frame 15 (frame 18: 130 s of CPU), so BMC stops at 18, short of
      // the bound (its bounded response is VACUOUS there, the log says so); the safety properties hold to 18.
      UnitCase(
        "readeng",
        () => new FormalReadEngineTop(sys2, e, "readeng"),
        re,
        18,
        deep = true,
        terms =
          s"slots ${FormalReadEngineTop.slots(sys2)}, max beats $beats, L ${e.readLatency}, S ${e.stall}, H ${e.takeStall}"
      )
    )
  }
}

/** The abstract core that stands in for RtAccel in the system proofs: the
  * core's own properties (exactly once, no overflow, ray conservation) are
  * checked on RtAccel itself (FormalTop); here only its promise at the ports
  * is kept. `numRayIds` slots: a ray is taken when a slot is free; it reads
  * a node record, a triangle record, both or neither (free; free addresses,
  * tag = slot), answers in any order; then its hit (the ray's number, every other field
  * free) is offered until taken. It may refuse a memory answer at most
  * `stall` cycles in a row. Asserted: each answer comes for a read that
  * waits (`core_read_answer_once`).
  *
  * Module name and ports are RtAccel's, so Yosys reads it over the real core
  * (`read_verilog -overwrite`); it instantiates nothing but FormalAnySeq.
  */
class FormalCoreStub(cfg: AccelConfig, name: String, stall: Int) extends Module {
  override def desiredName = name
  // RtAccel's node port: PrepFetch's and the traversal's requests share it, one tag bit says whose (TaggedPortArbiter.shared).
  private val nodePort: MemPortParams = PrepFetch.port(cfg).copy(tagBits = PrepFetch.port(cfg).tagBits + 1)
  val io = IO(new Bundle {
    val rays = Flipped(Decoupled(new RayIn))
    val hits = Decoupled(new HitOut(cfg))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val triBase = Input(UInt(cfg.addrBits.W))
    val nodeMem = new MemPort(nodePort)
    val triMem = new MemPort(LeafIntersect.port(cfg))
    val perf = Output(new PerfCounters)
    val broken = Output(Bool())
  })
  private val n = cfg.numRayIds
  private val busyReg = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val numberReg = Reg(Vec(n, UInt(32.W)))
  // Per port and slot: the read still to issue, the read waiting for its answer.
  private val issueRegs = Seq.fill(2)(RegInit(VecInit(Seq.fill(n)(false.B))))
  private val waitRegs = Seq.fill(2)(RegInit(VecInit(Seq.fill(n)(false.B))))
  private val ports = Seq(io.nodeMem, io.triMem)

  private val free = PriorityEncoder(busyReg.map(!_))
  io.rays.ready := !busyReg.asUInt.andR
  for (((port, issue), wait) <- ports.zip(issueRegs).zip(waitRegs)) {
    val who = PriorityEncoder(issue)
    port.req.valid := issue.asUInt.orR
    port.req.bits.addr := FormalAnySeq(UInt(port.p.addrBits.W))
    port.req.bits.tag := who
    when(port.req.fire) { issue(who) := false.B; wait(who) := true.B }
    val stallReg = RegInit(0.U(log2Ceil(stall + 1).max(1).W))
    port.resp.ready := (if (stall == 0) true.B else !FormalAnySeq(Bool()) || stallReg === stall.U)
    when(port.resp.valid && !port.resp.ready) { stallReg := stallReg + 1.U }.otherwise { stallReg := 0.U }
    val t = port.resp.bits.tag
    assert(
      !port.resp.fire || (t < n.U && wait(t(log2Ceil(n) - 1, 0))),
      "core_read_answer_once: a memory answer for no waiting read"
    )
    when(port.resp.fire) { wait(t(log2Ceil(n) - 1, 0)) := false.B }
    when(io.rays.fire) { issue(free) := FormalAnySeq(Bool()) }
  }
  when(io.rays.fire) { busyReg(free) := true.B; numberReg(free) := io.rays.bits.number }

  private val doneVec = VecInit((0 until n).map(i => busyReg(i) && (issueRegs ++ waitRegs).map(!_(i)).reduce(_ && _)))
  private val out = PriorityEncoder(doneVec)
  io.hits.valid := doneVec.asUInt.orR
  io.hits.bits := FormalAnySeq(new HitOut(cfg))
  io.hits.bits.number := numberReg(out)
  when(io.hits.fire) { busyReg(out) := false.B }

  io.perf := 0.U.asTypeOf(new PerfCounters)
  io.broken := false.B
}

/** SystemCore (1 core, the core replaced by FormalCoreStub in the proof) in
  * a formal environment (docs/formal.md, "System level"):
  *  - host: a script of AXI-Lite writes (LOAD_SCENE, IRQ_ENABLE, RAY_BASE,
  *    HIT_BASE, RAY_COUNT; on the scene interrupt START, then IRQ_ENABLE = DONE).
  *    RAY_BASE, HIT_BASE (64-aligned, the buffers inside the 4 KB space) and
  *    RAY_COUNT (1..maxRays) are free, chosen once;
  *  - m_axi slave: AR refused at most `stall` cycles in a row and while it
  *    holds `bursts` bursts; beats of one ID in order, bursts of different IDs
  *    in any order and interleaved; a burst older than `readLatency` cycles
  *    takes the R channel (an overdue one each cycle), so every burst ends; data free,
  *    except the scene header at address 0 (valid, so the load succeeds; the node section
  *    is 0 or 64 bytes, free, so the node store is filled with one node or left empty);
  *    AW and W each refused at most `stall` cycles in a row, W only after its
  *    AW; B after at most `bLatency` refusals in a row;
  *  - monitor, by ray index (ray i is record i at RAY_BASE + 48 i, its hit
  *    record i at HIT_BASE + 32 i):
  *    `ray_block_read_once` a ray block is read from DDR once;
  *    `hit_in_buffer` every write is one 32-byte hit record inside [HIT_BASE, HIT_BASE + 32 RAY_COUNT);
  *    `hit_written_once` no hit record is written twice;
  *    `hit_after_fetch` a hit is written only for a ray read from DDR (none made up);
  *    `batch_conservation` at DONE every ray 0..RAY_COUNT-1 was read and its hit written (rays read =
  *    hits written + rays in flight, with none in flight at DONE);
  *    `system_ray_conservation` in every cycle, rays fetched = hits written + rays held unit by unit (SystemConservation);
  *    `batch_bounded_response` DONE comes within `bound(RAY_COUNT)` cycles of START (SystemBound).
  */
class FormalSystemTop(c: SystemCase, bound: Int => Int, dp: FormalDatapath) extends Module {
  override def desiredName = s"FormalTop_${c.name}"
  val io = IO(new Bundle {})
  private val sys = c.sys
  private val env = c.env
  private val dut = Module(new SystemCore(sys, dp))
  private val a = dut.io.axi
  private val h = dut.io.ctl
  private val addrBits = sys.axiAddrBits
  private val beatBits = log2Ceil(sys.axiDataBytes)
  private val rpb = sys.raysPerBlock
  private val maxBlocks = (env.maxRays + rpb - 1) / rpb
  private val space = 1 << addrBits
  require(env.maxRays <= 15, "FormalSystemTop: RAY_COUNT is held in 4 bits")

  // ---- The batch the environment chooses ----
  private val loadedReg = RegInit(false.B)
  private val rbReg = Reg(UInt(addrBits.W))
  private val hbReg = Reg(UInt(addrBits.W))
  private val countReg = Reg(UInt(4.W))
  private val (rbFree, hbFree, countFree) =
    (FormalAnySeq(UInt(addrBits.W)), FormalAnySeq(UInt(addrBits.W)), FormalAnySeq(UInt(4.W)))
  when(!loadedReg) { rbReg := rbFree; hbReg := hbFree; countReg := countFree; loadedReg := true.B }
  assume(
    loadedReg || (rbFree(5, 0) === 0.U && rbFree <= (space - maxBlocks * sys.rayBlockBytes).U &&
      hbFree(5, 0) === 0.U && hbFree <= (space - env.maxRays * SystemConfig.HitBytes).U &&
      countFree >= 1.U && countFree <= env.maxRays.U),
    "host_batch: aligned buffers inside the address space, 1..maxRays rays"
  )
  private val blocks = (countReg +& (rpb - 1).U) >> log2Ceil(rpb)

  // ---- Host: the AXI-Lite script ----
  private def reg(name: String) = RegisterMap.regs(RegisterMap.index(name)).offset
  // LOAD_SCENE first, the batch's registers while the scene loads; START on the scene interrupt, then the
  // interrupt is switched to DONE (IRQ_ENABLE) so that it rises only when the batch ends.
  // The window case first sets the DMA window: base and limit free (64-byte aligned; limit 0 is the whole space),
  // chosen once, written before any m_axi traffic (LOAD_SCENE comes after them).
  private val winBaseReg = Reg(UInt(addrBits.W))
  private val winLimitReg = Reg(UInt(addrBits.W))
  private val (winBaseFree, winLimitFree) = (FormalAnySeq(UInt(addrBits.W)), FormalAnySeq(UInt(addrBits.W)))
  when(!loadedReg) { winBaseReg := winBaseFree; winLimitReg := winLimitFree }
  assume(
    loadedReg || (winBaseFree(5, 0) === 0.U && winLimitFree(5, 0) === 0.U),
    "host_window: a window of whole 64-byte lines"
  )
  private val windowWrites: Seq[(Int, UInt)] =
    if (c.window) Seq(reg("WINDOW_BASE") -> winBaseReg, reg("WINDOW_LIMIT") -> winLimitReg) else Nil
  private val script: Seq[(Int, UInt)] = windowWrites ++ Seq(
    reg("CTRL") -> 2.U,
    reg("IRQ_ENABLE") -> 2.U,
    reg("RAY_BASE") -> rbReg,
    reg("HIT_BASE") -> hbReg,
    reg("RAY_COUNT") -> countReg,
    reg("CTRL") -> 1.U,
    reg("IRQ_ENABLE") -> 1.U
  )
  private val stepReg = RegInit(0.U(log2Ceil(script.size + 1).W))
  private val running = stepReg === script.size.U
  // START waits for the scene's interrupt.
  private val gate = MuxLookup(stepReg, true.B)(Seq((windowWrites.size + 5).U -> dut.io.interrupt))
  private val active = loadedReg && !running && gate
  private val awSentReg = RegInit(false.B)
  private val wSentReg = RegInit(false.B)
  h.aw.valid := active && !awSentReg
  h.aw.bits.addr := MuxLookup(stepReg, 0.U)(script.zipWithIndex.map { case ((ad, _), i) => i.U -> ad.U })
  h.aw.bits.prot := 0.U
  h.w.valid := active && !wSentReg
  h.w.bits.data := MuxLookup(stepReg, 0.U)(script.zipWithIndex.map { case ((_, d), i) => i.U -> d.pad(32) })
  h.w.bits.strb := "b1111".U
  h.b.ready := true.B
  h.ar.valid := false.B
  h.ar.bits := DontCare
  h.r.ready := true.B
  when(h.aw.fire) { awSentReg := true.B }
  when(h.w.fire) { wSentReg := true.B }
  when(h.b.fire) { stepReg := stepReg + 1.U; awSentReg := false.B; wSentReg := false.B }

  // ---- m_axi reads: the burst table (FormalAxiReadSlave) ----
  private def stalled(valid: Bool, ready: Bool): Bool = FormalAxiReadSlave.stalled(valid, ready, env.stall)
  private val slave = Module(new FormalAxiReadSlave(sys.axi, env.readLatency, env.stall, env.bursts))
  slave.io.ar <> a.ar
  a.r <> slave.io.r
  private val last = slave.io.r.bits.last
  private val header = Mux(FormalAnySeq(Bool()), FormalSystemTop.header(sys, 128), FormalSystemTop.header(sys, 64))
  slave.io.data := Mux(slave.io.beatAddr === 0.U, header, FormalAnySeq(UInt(sys.axiDataBits.W)))

  // ---- Rays read from DDR: a ray block is the only 3-beat burst (node 64 B, triangle 48 B, header 64 B take <= 2) ----
  require(sys.rayBlockBytes == 3 * sys.axiDataBytes, "FormalSystemTop: ray blocks are told apart as 3-beat bursts")
  private val blockReadRegs = RegInit(VecInit(Seq.fill(maxBlocks)(false.B)))
  for (k <- 0 until maxBlocks) {
    val isBlock =
      a.r.fire && last && slave.io.burstLen === 2.U && slave.io.burstAddr === rbReg + (k * sys.rayBlockBytes).U && k.U < blocks
    assert(!isBlock || !blockReadRegs(k), s"ray_block_read_once: ray block $k read twice")
    when(isBlock) { blockReadRegs(k) := true.B }
  }
  private val inBatch = VecInit((0 until env.maxRays).map(i => i.U < countReg))
  private val fetched = VecInit((0 until env.maxRays).map(i => blockReadRegs(i / rpb) && inBatch(i)))

  // ---- m_axi writes: AW queue, W after its AW, B ----
  private val awQ = Module(new Queue(UInt(addrBits.W), 2))
  private val awStall = stalled(a.aw.valid, a.aw.ready)
  awQ.io.enq.valid := a.aw.valid && !awStall
  awQ.io.enq.bits := a.aw.bits.addr
  a.aw.ready := awQ.io.enq.ready && !awStall
  a.w.ready := awQ.io.deq.valid && !stalled(a.w.valid, a.w.ready)
  awQ.io.deq.ready := a.w.fire
  // A W beat carries whole 32-byte hit records (HitDma writes a record alone or two neighbours as one line):
  // strobe group g (32 bytes) all set or all clear, at least one set, record (beat - HIT_BASE) / 32 + g in the batch.
  private val groups = (0 until sys.axiDataBytes / SystemConfig.HitBytes).map(g =>
    a.w.bits.strb(SystemConfig.HitBytes * (g + 1) - 1, SystemConfig.HitBytes * g)
  )
  private val groupOn = groups.map(_.andR)
  private val offset = awQ.io.deq.bits - hbReg
  private val firstIndex = offset(addrBits - 1, log2Ceil(SystemConfig.HitBytes))
  private val indices = groups.indices.map(g => firstIndex + g.U)
  private val inBuffer = awQ.io.deq.bits >= hbReg && a.w.bits.last && groupOn.reduce(_ || _) &&
    groups.zip(groupOn).map { case (x, on) => on || x === 0.U }.reduce(_ && _) &&
    groupOn.zip(indices).map { case (on, i) => !on || i < countReg }.reduce(_ && _)
  private val writtenRegs = RegInit(VecInit(Seq.fill(env.maxRays)(false.B)))
  assert(!a.w.fire || inBuffer, "hit_in_buffer: a write outside the hit buffer, or not whole hit records")
  for ((on, i) <- groupOn.zip(indices)) {
    val idx = i(log2Ceil(env.maxRays) - 1, 0)
    val w = a.w.fire && inBuffer && on
    assert(!w || !writtenRegs(idx), "hit_written_once: a hit record written twice")
    assert(!w || fetched(idx), "hit_after_fetch: a hit written for a ray not read from DDR")
    when(w) { writtenRegs(idx) := true.B }
  }
  if (!c.window) SystemConservation(dut, countReg, rbReg, Mux(a.w.fire, PopCount(groupOn), 0.U), maxBlocks)
  private val pendingReg = RegInit(0.U(5.W))
  private val bStallReg = RegInit(0.U(log2Ceil(env.bLatency + 1).max(1).W))
  a.b.valid := pendingReg =/= 0.U && (FormalAnySeq(Bool()) || bStallReg === env.bLatency.U)
  a.b.bits.id := 0.U
  a.b.bits.resp := Axi4.RespOkay.U
  when(a.b.valid && !a.b.ready) { bStallReg := bStallReg + 1.U }.otherwise { bStallReg := 0.U }
  pendingReg := pendingReg + a.w.fire.asUInt - a.b.fire.asUInt

  // ---- The DMA window: no burst outside it is even offered on m_axi ----
  if (c.window) {
    val top = Mux(winLimitReg === 0.U, space.U, winLimitReg)
    def inside(addr: UInt, len: UInt): Bool = addr >= winBaseReg && (addr +& ((len +& 1.U) << beatBits)) <= top
    // The window registers hold the host's values from the B of the WINDOW_LIMIT write on (step 2); nothing
    // reaches m_axi before LOAD_SCENE (step 2 as well), so the check covers every burst.
    val set = stepReg >= windowWrites.size.U
    assert(
      !(set && a.ar.valid) || inside(a.ar.bits.addr, a.ar.bits.len),
      "window_kept: an m_axi read burst offered outside the window"
    )
    assert(
      !(set && a.aw.valid) || inside(a.aw.bits.addr, a.aw.bits.len),
      "window_kept: an m_axi write burst offered outside the window"
    )
    assert(set || !(a.ar.valid || a.aw.valid), "window_kept: an m_axi burst before the window was set")
  }

  // ---- The batch: DONE (the interrupt after START); with a window, a refused burst ends it early ----
  private val done = running && dut.io.interrupt
  private val all =
    VecInit(inBatch.zip(writtenRegs).zip(fetched).map { case ((in, w), f) => in === w && in === f }).asUInt.andR
  if (!c.window)
    assert(!done || all, "batch_conservation: DONE with a ray of the batch not read or its hit not written once")
  private val ageBits = log2Ceil((1 to env.maxRays).map(bound).max + 2)
  private val ageReg = RegInit(0.U(ageBits.W))
  private val doneSeenReg = RegInit(false.B)
  when(done) { doneSeenReg := true.B }
  when(running && !doneSeenReg) { ageReg := ageReg + 1.U }
  private val limit = MuxLookup(countReg, 0.U)((1 to env.maxRays).map(r => r.U -> bound(r).U(ageBits.W)))
  if (!c.window)
    assert(
      !(running && !doneSeenReg && !done && ageReg >= limit),
      "batch_bounded_response: no DONE within the derived bound after START"
    )
}

object FormalSystemTop {

  /** The core's datapath in the system's SystemVerilog (replaced by the stub in the model; it names the core's module). */
  val datapath = new FormalDatapath(prepLatency = 1, boxLatency = 2, primLatency = 2)

  /** A valid image header (docs/memory-format.md) for `sys`: nodes at 64, triangles at `triOffset`
    * (128: one node, which the store holds; 64: none, the store stays empty). */
  def header(sys: SystemConfig, triOffset: Int): UInt = {
    val magic = java.nio.ByteBuffer.wrap(MemoryImage.Magic).order(java.nio.ByteOrder.LITTLE_ENDIAN)
    val words = Array.fill(16)(BigInt(0))
    words(0) = BigInt(magic.getInt(0).toLong & 0xffffffffL)
    words(1) = BigInt(magic.getInt(4).toLong & 0xffffffffL)
    words(2) = BigInt(MemoryImage.Version)
    words(5) = 64; words(6) = triOffset
    words(7) = sys.core.layout.nodeBytes; words(8) = MemoryImage.TriBytes
    words(10) = 1; words(11) = sys.core.layout.code
    val v = words.zipWithIndex.map { case (w, k) => w << (32 * k) }.reduce(_ | _)
    v.U(sys.axiDataBits.W)
  }
}

/** Writes the system proofs' SystemVerilog for `make formal-system`:
  * formal_<case>.sv (FormalSystemTop, with the real RtAccel inside),
  * stub_<case>.sv (FormalCoreStub under RtAccel's module name, read over it),
  * formal_<case>.props and system-cases.txt (name, depth, bound for RAY_COUNT = 1).
  *
  * Usage: EmitFormalSystem --out build/formal [--bound-cut N]  (N: a probe's cut bound for every RAY_COUNT)
  */
object EmitFormalSystem {
  def main(args: Array[String]): Unit = {
    val out = args.sliding(2).collectFirst { case Array("--out", d) => java.nio.file.Paths.get(d) }
      .getOrElse(throw new IllegalArgumentException("EmitFormalSystem: usage: --out <dir>"))
    java.nio.file.Files.createDirectories(out)
    java.nio.file.Files.writeString(out.resolve("FormalAnySeq.v"), FormalAnySeq.verilog)
    val dp = FormalSystemTop.datapath
    val lines = for (c <- SystemCase.all) yield {
      val b = (r: Int) => SystemBound(c, r).map(_.cycles).sum
      val sv = ForYosys(rtaccel.tools.Synth.emit(new FormalSystemTop(c, b, dp)))
      val core = "module (RtAccel_[A-Za-z0-9_]+)\\(".r.findFirstMatchIn(sv).map(_.group(1))
        .getOrElse(throw new IllegalStateException("EmitFormalSystem: no RtAccel module in the system's SystemVerilog"))
      val stub = ForYosys(rtaccel.tools.Synth.emit(new FormalCoreStub(c.sys.core, core, c.env.stall)))
      java.nio.file.Files.writeString(out.resolve(s"formal_${c.name}.sv"), sv)
      java.nio.file.Files.writeString(out.resolve(s"stub_${c.name}.sv"), stub)
      // The real core's assertions are in the system's SystemVerilog but not in the model (the stub replaces it).
      val coreOnly = ForYosys.names(ForYosys(rtaccel.tools.Synth.emit(new RtAccel(c.sys.core, dp)))).toSet
      val props = (ForYosys.names(sv).filterNot(coreOnly) ++ ForYosys.names(stub)).distinct
      java.nio.file.Files.writeString(out.resolve(s"formal_${c.name}.props"), props.mkString("", "\n", "\n"))
      for (r <- 1 to c.env.maxRays)
        println(s"EmitFormalSystem: ${c.name} RAY_COUNT $r: bound ${b(r)} = " + SystemBound(c, r).map(t =>
          s"${t.name} ${t.cycles}"
        ).mkString(" + "))
      s"${c.name} ${c.depth} ${b(1)}\n"
    }
    java.nio.file.Files.writeString(out.resolve("system-cases.txt"), lines.mkString)
    // The system's units alone (FormalSystemUnits), each checked past its derived bound: make formal-system-units.
    val units = for (u <- SystemCase.units) yield {
      val sv = ForYosys(rtaccel.tools.Synth.emit(u.top()))
      java.nio.file.Files.writeString(out.resolve(s"formal_${u.name}.sv"), sv)
      java.nio.file.Files.writeString(
        out.resolve(s"formal_${u.name}.props"),
        ForYosys.names(sv).mkString("", "\n", "\n")
      )
      println(s"EmitFormalSystem: unit ${u.name} bound ${u.bound} (${u.terms}), depth ${u.depth}")
      s"${u.name} ${u.depth} ${u.bound}\n"
    }
    java.nio.file.Files.writeString(out.resolve("system-units.txt"), units.mkString)
  }
}

/** The cycles from START (its B response to the host) to DONE for a batch of
  * `rays` rays, derived term by term from the configuration and the
  * environment (docs/formal.md, "System level"), never chosen. Loose where
  * the units overlap: every ray's trip is counted one after the other.
  */
object SystemBound {
  def apply(c: SystemCase, rays: Int): Seq[ResponseBound.Term] = {
    val e = c.env
    val s = e.stall
    val blocks = (rays + c.sys.raysPerBlock - 1) / c.sys.raysPerBlock
    // A record read: client arbiter 1, ReadEngine slot register 1, AR register 1, AR queue 1, slave refusals s + 1;
    // the burst is overdue after L cycles, then waits at most for every beat of the bursts the slave holds
    // (3 beats each at most: a ray block); R stage 1, bank write 1, completion queue 1, select 1, read 1, output queue 1;
    // the client refuses the answer at most s cycles.
    val read = 4 + (s + 1) + e.readLatency + 3 * e.bursts + 6 + s
    Seq(
      ResponseBound.Term("start (CTRL write to the ray DMA's first request)", 2),
      // Each block: its read; the block queue and unpack 1.
      ResponseBound.Term(s"ray blocks ($blocks)", blocks * (read + 1)),
      // Each ray, one after the other: hand-over 1, the core stub's two reads through one arbiter (+1), hit offer 1;
      // HitDma arbiter and queue 2, WriteEngine queues 1, AW and W refusals s + 1, the slave's B after at most bLatency refusals + 1.
      ResponseBound.Term(s"rays ($rays)", rays * (1 + read + 1 + 1 + 2 + 1 + (s + 1) + e.bLatency + 1)),
      // A hit waiting in HitDma's pair buffer for its neighbour leaves with it (the neighbour's trip, above) or, once
      // the batch's last hit is taken, alone: one line per slot, each through the hit queue 1, WriteEngine queues 1,
      // AW and W refusals s + 1 and the slave's B after at most bLatency refusals + 1.
      ResponseBound.Term(
        s"pair buffer flush (${c.sys.hitPairSlots} slots)",
        c.sys.hitPairSlots * (2 + (s + 1) + e.bLatency + 1)
      ),
      // writesDone reaches RAY_COUNT: finish 1, IRQ_STATUS 1, the interrupt register 1.
      ResponseBound.Term("done", 3)
    )
  }
}
