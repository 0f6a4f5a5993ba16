package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.axi.Axi4
import rtaccel.scene.MemoryImage
import rtaccel.system.{RegisterMap, SystemConfig, SystemCore}

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
