package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Master, AxiLite}
import rtaccel.{Datapath, ErrorFlags, PerfCounter, RtAccel}

/** The system in Chisel bundle form (RtAccelSystem gives it Vivado's port
  * names): the register block, the scene loader, the ray and hit DMAs, `cores`
  * RtAccel cores and the MemoryFabric that puts all their reads and the hit
  * writes on one AXI4 master.
  *
  * Batch: START (with SCENE_READY, not BUSY, RAY_BASE and HIT_BASE 64-byte
  * aligned) latches RAY_BASE, RAY_COUNT and HIT_BASE; DONE when the B
  * responses the fabric has received since START acknowledge RAY_COUNT hit
  * records (every hit written; a line carries one or two). The core
  * bases change only at LOAD_SCENE, which is refused while BUSY, so no ray is
  * in flight when they change.
  *
  * Faults (docs/faults.md): ABORT, an AXI error or a refused burst stop the
  * batch: no more rays are handed out, the rays in flight finish and their
  * hits are written, then the batch ends (STATUS.ABORTED, RAYS_ISSUED rays
  * done). The watchdog ends a batch or a load with no progress for
  * WATCHDOG_CYCLES cycles (STATUS.TIMEOUT, IRQ FAULT). SOFT_RESET resets all
  * but the register block (which holds the DMA window and its lock); it is
  * the way out of every sticky fault. Every m_axi burst passes the
  * WindowGuard.
  */
class SystemCore[T <: Data](val sys: SystemConfig, val dp: Datapath[T]) extends Module {
  val io = IO(new Bundle {
    val ctl = Flipped(new AxiLite(RegisterMap.AddrBits, 32))
    val axi = new Axi4Master(sys)
    val interrupt = Output(Bool())
  })
  private val cfg = sys.core
  // ---- registers: outside the soft reset, so the window and its lock hold until aresetn ----
  private val regs = Module(new AxiLiteRegs)
  regs.io.axi <> io.ctl
  private val rm = RegisterMap
  regs.io.hw.foreach(_ := 0.U)
  private def hw(name: String): UInt = regs.io.hw(rm.index(name))
  private def value(name: String): UInt = regs.io.value(rm.index(name))
  private def bit(reg: String, field: String): Int = rm.field(reg, field).lsb
  private val ctrl = regs.io.pulse(rm.index("CTRL"))
  regs.io.lock := value("WINDOW_LOCK")(bit("WINDOW_LOCK", "LOCK"))

  /** SOFT_RESET: one cycle of synchronous reset for everything below but the register block. */
  private val softResetReg = RegNext(ctrl(bit("CTRL", "SOFT_RESET")), false.B)
  private val dpReset = reset.asBool || softResetReg

  private def underSoftReset[M <: RawModule](m: => M): M = withReset(dpReset)(Module(m))
  private val cores = Seq.fill(sys.cores)(underSoftReset(new RtAccel(cfg, dp)))
  private val loader = underSoftReset(new SceneLoader(sys))
  private val rayDma = underSoftReset(new RayDma(sys))
  private val hitDma = underSoftReset(new HitDma(sys))
  private val readers =
    cores.flatMap(c => Seq(c.io.nodeMem.p, c.io.triMem.p)) ++ Seq(SceneLoader.port(sys), RayDma.port(sys))
  private val fabric = underSoftReset(new MemoryFabric(
    sys,
    readers,
    cores.flatMap(_ => Seq(true, false)) ++ Seq(false, false),
    cores.flatMap(_ => Seq(false, true)) ++ Seq(false, false)
  ))
  private val guard = underSoftReset(new WindowGuard(sys.axi))
  for ((c, i) <- cores.zipWithIndex) {
    fabric.io.readers(2 * i) <> c.io.nodeMem
    fabric.io.readers(2 * i + 1) <> c.io.triMem
    // A core fetches its root node after reset at its nodeBase, which is 0 until a scene's header has passed the
    // loader's checks: that read, at an address nothing says is the scene's, waits (held, not dropped) until the
    // bases are the scene's. Otherwise, after SOFT_RESET under a DMA window that leaves out address 0, it is
    // refused and sets WINDOW_ERROR before any scene can load. The bases and `basesValid` change in the same
    // cycle; FetchBVH drops a request it still holds for the old base in that cycle (it offers it there), and the
    // port opens a cycle after `basesValid` rises, so the fabric only ever sees the request for the scene's root.
    val ok = loader.io.basesValid && RegNext(loader.io.basesValid, false.B)
    fabric.io.readers(2 * i).req.valid := c.io.nodeMem.req.valid && ok
    c.io.nodeMem.req.ready := fabric.io.readers(2 * i).req.ready && ok
  }
  fabric.io.readers(2 * sys.cores) <> loader.io.mem
  fabric.io.readers(2 * sys.cores + 1) <> rayDma.io.mem
  fabric.io.store <> loader.io.store
  fabric.io.triStore <> loader.io.triStore
  fabric.io.write <> hitDma.io.write
  guard.io.in <> fabric.io.axi
  io.axi <> guard.io.out
  guard.io.base := value("WINDOW_BASE")
  guard.io.limit := value("WINDOW_LIMIT")

  // Batch state: cleared by SOFT_RESET like the modules above.
  private val activeReg = RegInit(false.B)
  private val doneReg = RegInit(false.B)
  private val brokenReg = RegInit(false.B)
  private val stopReg = RegInit(false.B) // ABORT seen in this batch
  private val abortedReg = RegInit(false.B)
  private val timeoutReg = RegInit(false.B)
  private val windowErrReg = RegInit(false.B)
  private val refusedReg = RegInit(0.U(32.W))
  private val faultAddrReg = RegInit(0.U(32.W))
  private val writesBaseReg = RegInit(0.U(32.W))
  private val countReg = RegInit(0.U(32.W))
  private val issuedReg = RegInit(0.U(32.W))
  private val busy = activeReg || loader.io.busy

  /** A fault that only SOFT_RESET clears: START and LOAD_SCENE wait for it. */
  private val fault = brokenReg || fabric.io.axiError || timeoutReg || windowErrReg
  private val aligned = value("RAY_BASE")(5, 0) === 0.U && value("HIT_BASE")(5, 0) === 0.U
  private val start = ctrl(bit("CTRL", "START")) && !busy && loader.io.ready && aligned && !fault
  private val load = ctrl(bit("CTRL", "LOAD_SCENE")) && !busy && !fault
  private val clear = ctrl(bit("CTRL", "CLEAR_COUNTERS"))
  private val abort = ctrl(bit("CTRL", "ABORT")) && activeReg
  // The batch's hit records written, registered (a cycle late; 0 in the cycle after START, before the new base
  // counts): the subtraction and the compares behind it, into the batch's finish, were one path, 8.23 ns with 3
  // cores (docs/fmax.md). A count a cycle old never exceeds the true one, so every test on it below holds late,
  // never early.
  private val raysDoneReg = RegInit(0.U(32.W))
  private val raysDone = raysDoneReg
  // The two 32-bit equalities behind the finish, each compared from registers and registered (a cycle later
  // again): compared in the finish's cycle, the done count's compare with RAY_COUNT ran through the finish into
  // the batch's flags, 5.83 ns (docs/fmax.md). Both are false in the cycle after START (cleared by it), so a new
  // batch never sees the last one's. Each holds late, never early: `allDoneReg` because the done count never
  // passes RAY_COUNT; `issuedDoneReg` because it is taken only in a cycle that hands out no ray, so the
  // issued count it compared is still this cycle's, and the done count never passes the issued one.
  private val allDoneReg = RegInit(false.B)
  private val issuedDoneReg = RegInit(false.B)
  allDoneReg := !start && raysDoneReg === countReg
  issuedDoneReg := !start && raysDoneReg === issuedReg && !rayDma.io.rays.fire

  /** The batch stops handing out rays: ABORT, or a fault that makes its hits untrustworthy. */
  private val stopping = stopReg || fabric.io.axiError || windowErrReg
  // Stopped: every ray handed out has its hit written (each ray handed out gives exactly one hit record).
  private val stopped = stopping && rayDma.io.idle && issuedDoneReg
  private val watchdogFired = Wire(Bool())
  private val finish = activeReg && (allDoneReg || stopped || watchdogFired)
  raysDoneReg := Mux(start, 0.U, fabric.io.writesDone - writesBaseReg)
  when(start) {
    activeReg := true.B; doneReg := false.B; abortedReg := false.B; stopReg := false.B; issuedReg := 0.U
    writesBaseReg := fabric.io.writesDone; countReg := value("RAY_COUNT")
  }
  when(abort) { stopReg := true.B }
  when(rayDma.io.rays.fire) { issuedReg := issuedReg + 1.U }
  when(finish) {
    activeReg := false.B
    doneReg := allDoneReg && !stopping && !watchdogFired
    abortedReg := stopping && !watchdogFired
  }
  when(guard.io.refused =/= 0.U) {
    windowErrReg := true.B
    refusedReg := refusedReg + guard.io.refused
    when(!windowErrReg) { faultAddrReg := guard.io.refusedAddr }
  }

  // ---- watchdog: cycles of a batch or scene load without a ray handed out, a hit written or a scene beat ----
  // The count is kept one ahead (`watchNextReg` = the count + 1: the count it will be unless progress clears it),
  // so that whether it has reached WATCHDOG_CYCLES is compared a cycle early, from registers, into `watchOverReg`:
  // compared in the cycle it fires, the 32-bit compare ran through the batch's finish into `activeReg`, 5.42 ns
  // (docs/fmax.md). The watchdog fires at the same count as before; WATCHDOG_CYCLES is taken a cycle later.
  private val watchNextReg = RegInit(1.U(32.W))
  private val watchOverReg = RegInit(false.B) // the count >= WATCHDOG_CYCLES as of the cycle before
  private val limitSetReg = RegInit(false.B) // WATCHDOG_CYCLES =/= 0 as of the cycle before
  private val progress = rayDma.io.rays.fire || io.axi.b.fire || (loader.io.busy && io.axi.r.fire)
  private val limit = value("WATCHDOG_CYCLES")
  private val watchClear = !busy || progress || timeoutReg
  when(watchClear) { watchNextReg := 1.U }.otherwise { watchNextReg := watchNextReg + 1.U }
  // Next cycle's count is 0 when cleared (0 >= limit: limit is 0), else watchNextReg.
  watchOverReg := Mux(watchClear, limit === 0.U, watchNextReg >= limit)
  limitSetReg := limit =/= 0.U
  watchdogFired := busy && limitSetReg && watchOverReg && !timeoutReg
  when(watchdogFired) { timeoutReg := true.B }
  rayDma.io.stop := stopping || timeoutReg

  when(softResetReg) {
    activeReg := false.B; doneReg := false.B; brokenReg := false.B; stopReg := false.B; abortedReg := false.B
    timeoutReg := false.B; windowErrReg := false.B; refusedReg := 0.U; faultAddrReg := 0.U; writesBaseReg := 0.U
    issuedReg := 0.U; watchNextReg := 1.U; watchOverReg := limit === 0.U; raysDoneReg := 0.U; allDoneReg := false.B;
    issuedDoneReg := false.B
  }

  loader.io.start := load
  loader.io.sceneBase := value("SCENE_BASE")
  rayDma.io.start := start; rayDma.io.rayCount := value("RAY_COUNT")
  hitDma.io.start := start; hitDma.io.rayCount := value("RAY_COUNT")
  // Stopped and idle, RayDma hands out no more rays: once HitDma has taken issuedReg hits, a hit waiting for its
  // line's partner waits for a ray that was never handed out.
  hitDma.io.stop := stopping && rayDma.io.idle; hitDma.io.issued := issuedReg
  rayDma.io.rayBase := value("RAY_BASE")
  hitDma.io.hitBase := value("HIT_BASE")

  // ---- rays to the first ready core at or after the round-robin pointer ----
  private val n = sys.cores
  private val ptrBits = log2Ceil(n).max(1)
  private val ptrReg = RegInit(0.U(ptrBits.W))
  private val order =
    (0 until n).map(k => Mux(ptrReg +& k.U >= n.U, ptrReg +& k.U - n.U, ptrReg +& k.U)(ptrBits - 1, 0))
  private val readyVec = VecInit(cores.map(_.io.rays.ready))
  private val anyReady = readyVec.asUInt.orR
  private val pick = if (n == 1) 0.U else PriorityMux(order.map(readyVec(_)), order)
  for ((c, i) <- cores.zipWithIndex) {
    c.io.rays.valid := rayDma.io.rays.valid && anyReady && pick === i.U
    c.io.rays.bits := rayDma.io.rays.bits
    c.io.nodeBase := loader.io.nodeBase
    c.io.triBase := loader.io.triBase
    hitDma.io.hits(i) <> c.io.hits
  }
  rayDma.io.rays.ready := anyReady
  when(rayDma.io.rays.fire) { ptrReg := Mux(pick === (n - 1).U, 0.U, pick + 1.U) }

  private val coreBroken = cores.map(_.io.broken).reduce(_ || _)
  when(coreBroken || rayDma.io.broken || hitDma.io.broken) { brokenReg := true.B }

  // ---- status, interrupt ----
  private val irqDone = bit("IRQ_STATUS", "DONE")
  private val irqScene = bit("IRQ_STATUS", "SCENE")
  hw("IRQ_STATUS") := (finish.asUInt << irqDone) | (loader.io.finished.asUInt << irqScene) |
    (watchdogFired.asUInt << bit("IRQ_STATUS", "FAULT"))
  io.interrupt := RegNext((value("IRQ_STATUS") & value("IRQ_ENABLE")).orR, false.B)
  private def at(reg: String, field: String, b: Bool): UInt = b.asUInt << bit(reg, field)
  hw("STATUS") := at("STATUS", "BUSY", busy) | at("STATUS", "DONE", doneReg) | at(
    "STATUS",
    "SCENE_READY",
    loader.io.ready
  ) |
    at("STATUS", "SCENE_ERROR", loader.io.error) | at("STATUS", "BROKEN", brokenReg) | at(
      "STATUS",
      "AXI_ERROR",
      fabric.io.axiError
    ) |
    at("STATUS", "ABORTED", abortedReg) | at("STATUS", "TIMEOUT", timeoutReg) | at(
      "STATUS",
      "WINDOW_ERROR",
      windowErrReg
    )
  hw("SCENE_ERROR_CODE") := loader.io.errorCode
  hw("CONFIG_CORES") := n.U
  hw("CONFIG_LAYOUT") := cfg.layout.code.U
  hw("CONFIG_RAY_IDS") := cfg.numRayIds.U
  hw("CONFIG_STACK_DEPTH") := cfg.stackDepth.U
  hw("CONFIG_FLOAT") := ((cfg.triFloat.expBits << 8) | cfg.triFloat.manBits).U
  hw("CONFIG_NODE_STORE_BYTES") := sys.nodeStoreBytes.U
  hw("CONFIG_AXI_DATA_BITS") := sys.axiDataBits.U
  hw("RAYS_DONE") := raysDone
  hw("RAYS_ISSUED") := issuedReg
  hw("WINDOW_REFUSED") := refusedReg
  hw("WINDOW_FAULT_ADDR") := faultAddrReg
  for ((b, name) <- rm.errorFlags) hw(s"ERR_COUNT_$name") := hitDma.io.errCount(b)

  // ---- 64-bit counters: since CLEAR_COUNTERS (a snapshot of the running sums is subtracted) ----
  // The cores' counts are summed into a register: a 64-bit sum of the cores' counters and the snapshot's
  // subtraction after it were two carry chains in one cycle, SystemCore's longest path (docs/fmax.md). The
  // registered sum runs a cycle behind, and so does its snapshot, so a counter still counts exactly the events
  // since CLEAR_COUNTERS, a cycle later.
  private def sum(f: rtaccel.PerfCounters => UInt): UInt =
    RegNext(cores.map(c => f(c.io.perf)).reduce(_ + _), 0.U(64.W))
  // m_axi's events are registered before they are counted (a cycle behind, as the sums above): a W or AR handshake
  // comes through WindowGuard's window compare, and that chain ending in the count's add was SystemCore's longest
  // path, 5.24 ns (docs/fmax.md).
  private def count(event: Bool): UInt = PerfCounter(RegNext(event, false.B).asUInt)
  private val a = io.axi
  private val cyclesReg = RegInit(0.U(64.W))
  when(start || softResetReg) { cyclesReg := 0.U }.elsewhen(activeReg) { cyclesReg := cyclesReg + 1.U }
  private val running: Seq[(String, UInt)] = Seq(
    "RAYS_IN" -> sum(_.raysIn),
    "HITS_OUT" -> sum(_.hitsOut),
    "NODE_FETCHES" -> sum(_.nodeFetches),
    "TRI_FETCHES" -> sum(_.triFetches),
    "BOX_TESTS" -> sum(_.boxTests),
    "CHILD_BOX_TESTS" -> sum(_.childBoxTests),
    "TRI_TESTS" -> sum(_.triTests),
    "DECISIONS" -> sum(_.decisions),
    "LEAF_RETURNS" -> sum(_.leafReturns),
    "NODE_STORE_HITS" -> fabric.io.stats.nodeStoreHits,
    "NODE_STORE_MISSES" -> fabric.io.stats.nodeStoreMisses,
    "AXI_READ_BEATS" -> count(a.r.fire),
    "AXI_WRITE_BEATS" -> count(a.w.fire),
    "AXI_READ_STALL" -> count(a.ar.valid && !a.ar.ready),
    "IN_FLIGHT_SUM" -> sum(_.inFlightSum)
  )
  require(
    running.map(_._1).toSet + "CYCLES" == rm.counters.map(_._1).toSet,
    "SystemCore: every RegisterMap counter has a source"
  )
  private def show(name: String, v: UInt): Unit = { hw(s"${name}_LO") := v(31, 0); hw(s"${name}_HI") := v(63, 32) }
  show("CYCLES", cyclesReg)
  for ((name, v) <- running) {
    val baseReg = RegInit(0.U(64.W))
    // After SOFT_RESET the sources restart from 0, so must their snapshot.
    when(softResetReg) { baseReg := 0.U }.elsewhen(clear) { baseReg := v }
    show(name, v - baseReg)
  }
}
