package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Master, AxiLite}
import rtaccel.{Datapath, ErrorFlags, RtAccel}

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
  */
class SystemCore[T <: Data](val sys: SystemConfig, val dp: Datapath[T]) extends Module {
  val io = IO(new Bundle {
    val ctl = Flipped(new AxiLite(RegisterMap.AddrBits, 32))
    val axi = new Axi4Master(sys)
    val interrupt = Output(Bool())
  })
  private val cfg = sys.core
  private val cores = Seq.fill(sys.cores)(Module(new RtAccel(cfg, dp)))
  private val loader = Module(new SceneLoader(sys))
  private val rayDma = Module(new RayDma(sys))
  private val hitDma = Module(new HitDma(sys))
  private val readers =
    cores.flatMap(c => Seq(c.io.nodeMem.p, c.io.triMem.p)) ++ Seq(SceneLoader.port(sys), RayDma.port(sys))
  private val fabric = Module(new MemoryFabric(
    sys,
    readers,
    cores.flatMap(_ => Seq(true, false)) ++ Seq(false, false),
    cores.flatMap(_ => Seq(false, true)) ++ Seq(false, false)
  ))
  for ((c, i) <- cores.zipWithIndex) {
    fabric.io.readers(2 * i) <> c.io.nodeMem
    fabric.io.readers(2 * i + 1) <> c.io.triMem
  }
  fabric.io.readers(2 * sys.cores) <> loader.io.mem
  fabric.io.readers(2 * sys.cores + 1) <> rayDma.io.mem
  fabric.io.store <> loader.io.store
  fabric.io.triStore <> loader.io.triStore
  fabric.io.write <> hitDma.io.write
  io.axi <> fabric.io.axi

  // ---- registers ----
  private val regs = Module(new AxiLiteRegs)
  regs.io.axi <> io.ctl
  private val rm = RegisterMap
  regs.io.hw.foreach(_ := 0.U)
  private def hw(name: String): UInt = regs.io.hw(rm.index(name))
  private def value(name: String): UInt = regs.io.value(rm.index(name))
  private def bit(reg: String, field: String): Int = rm.field(reg, field).lsb
  private val ctrl = regs.io.pulse(rm.index("CTRL"))

  private val activeReg = RegInit(false.B)
  private val doneReg = RegInit(false.B)
  private val brokenReg = RegInit(false.B)
  private val writesBaseReg = RegInit(0.U(32.W))
  private val countReg = RegInit(0.U(32.W))
  private val busy = activeReg || loader.io.busy
  private val aligned = value("RAY_BASE")(5, 0) === 0.U && value("HIT_BASE")(5, 0) === 0.U
  private val start = ctrl(bit("CTRL", "START")) && !busy && loader.io.ready && aligned
  private val load = ctrl(bit("CTRL", "LOAD_SCENE")) && !busy
  private val clear = ctrl(bit("CTRL", "CLEAR_COUNTERS"))
  private val raysDone = fabric.io.writesDone - writesBaseReg
  private val finish = activeReg && raysDone === countReg
  when(start) {
    activeReg := true.B; doneReg := false.B
    writesBaseReg := fabric.io.writesDone; countReg := value("RAY_COUNT")
  }
  when(finish) { activeReg := false.B; doneReg := true.B }

  loader.io.start := load
  loader.io.sceneBase := value("SCENE_BASE")
  rayDma.io.start := start; rayDma.io.rayCount := value("RAY_COUNT")
  hitDma.io.start := start; hitDma.io.rayCount := value("RAY_COUNT")
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
  hw("IRQ_STATUS") := (finish.asUInt << irqDone) | (loader.io.finished.asUInt << irqScene)
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
  for ((b, name) <- rm.errorFlags) hw(s"ERR_COUNT_$name") := hitDma.io.errCount(b)

  // ---- 64-bit counters: since CLEAR_COUNTERS (a snapshot of the running sums is subtracted) ----
  private def sum(f: rtaccel.PerfCounters => UInt): UInt = cores.map(c => f(c.io.perf)).reduce(_ + _)
  private def count(event: Bool): UInt = {
    val r = RegInit(0.U(64.W))
    when(event) { r := r + 1.U }
    r
  }
  private val a = io.axi
  private val cyclesReg = RegInit(0.U(64.W))
  when(start) { cyclesReg := 0.U }.elsewhen(activeReg) { cyclesReg := cyclesReg + 1.U }
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
    when(clear) { baseReg := v }
    show(name, v - baseReg)
  }
}
