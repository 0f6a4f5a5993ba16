package rtaccel.sim

import chisel3._
import chiseltest._
import rtaccel.golden.{HitRecord, RayRecord}
import rtaccel.scene.MemoryImage
import rtaccel.sim.axi.{AxiAddrBeat, AxiMasterSignals, AxiMemoryModel, AxiMemoryParams, AxiWBeat, SparseMemory}
import rtaccel.system.{RegisterMap, SystemConfig}

import java.nio.{ByteBuffer, ByteOrder}

/** Drives a SystemSimTop cycle by cycle (no fork): the AXI4 memory model on
  * m_axi every cycle, and a single-threaded AXI4-Lite driver on s_axi whose
  * reads and writes step the clock (so the memory keeps serving meanwhile).
  */
final class SystemHarness[T <: Data](dut: SystemSimTop[T], p: AxiMemoryParams) {

  /** The slave's beat is the system's m_axi width (SystemConfig.axiDataBits). */
  val model = new AxiMemoryModel(p.copy(beatBytes = dut.sys.axiDataBytes))
  val mem: SparseMemory = model.mem
  private val sys = dut.sys
  private val io = dut.io
  var cycle = 0L

  /** B responses on m_axi: in a batch, one per hit record (WriteEngine writes each as a single-beat burst). */
  var writesAnswered = 0L
  dut.clock.setTimeout(0)

  // What the driver offers on s_axi this cycle.
  private var liteAw, liteW, liteAr, liteBReady, liteRReady = false
  private var ctrlNow, rNow, bNow, liteAddrNow, liteWNow = BigInt(-1)
  private def set(port: UInt, v: BigInt, now: BigInt): BigInt = { if (v != now) port.poke(v.U); v }
  private def field(word: BigInt, lsb: Int, w: Int): BigInt = (word >> lsb) & ((BigInt(1) << w) - 1)
  private def addr(word: BigInt) = AxiAddrBeat(
    field(word, 0, sys.axiIdBits).toInt,
    field(word, sys.axiIdBits, sys.axiAddrBits).toLong,
    field(word, sys.axiIdBits + sys.axiAddrBits, 8).toInt,
    field(word, sys.axiIdBits + sys.axiAddrBits + 8, 3).toInt,
    field(word, sys.axiIdBits + sys.axiAddrBits + 11, 2).toInt
  )
  var flags = BigInt(0)
  def flag(n: String): Boolean = flags.testBit(SystemSimTop.outFields.indexOf(n))

  /** One clock cycle: serve m_axi, offer the driver's s_axi signals, step. Returns the flags seen. */
  def step(): BigInt = {
    flags = io.flags.peek().litValue
    val s = model.slave
    val ar = Option.when(flag("arvalid"))(addr(io.ar.peek().litValue))
    val aw = Option.when(flag("awvalid"))(addr(io.aw.peek().litValue))
    val w = Option.when(flag("wvalid")) {
      val x = io.w.peek().litValue
      AxiWBeat(x >> (1 + sys.axiDataBits / 8), field(x, 1, sys.axiDataBits / 8), x.testBit(0))
    }
    for (r <- s.r)
      rNow = set(
        io.r,
        (r.data << (3 + sys.axiIdBits)) | (BigInt(r.id) << 3) | (BigInt(r.resp) << 1) | (if (r.last) 1 else 0),
        rNow
      )
    for (b <- s.b) bNow = set(io.b, (BigInt(b.id) << 2) | b.resp, bNow)
    val ins = Map(
      "arready" -> s.arReady,
      "awready" -> s.awReady,
      "wready" -> s.wReady,
      "rvalid" -> s.r.isDefined,
      "bvalid" -> s.b.isDefined,
      "lite_awvalid" -> liteAw,
      "lite_wvalid" -> liteW,
      "lite_bready" -> liteBReady,
      "lite_arvalid" -> liteAr,
      "lite_rready" -> liteRReady
    )
    ctrlNow = set(
      io.ctrl,
      SystemSimTop.inFields.zipWithIndex.map { case (n, i) => if (ins(n)) BigInt(1) << i else BigInt(0) }.sum,
      ctrlNow
    )
    if (s.b.isDefined && flag("bready")) writesAnswered += 1
    model.commit(AxiMasterSignals(
      ar,
      aw,
      w,
      rReady = s.r.isDefined && flag("rready"),
      bReady = s.b.isDefined && flag("bready")
    ))
    dut.clock.step()
    model.tick()
    cycle += 1
    flags
  }

  private def waitFor(what: String, limit: Int = 1000)(cond: => Boolean): Unit = {
    var n = 0
    while (!cond) {
      step(); n += 1;
      if (n > limit) throw new AssertionError(s"cycle $cycle: s_axi $what: no handshake in $limit cycles")
    }
  }

  /** An AXI4-Lite write; returns BRESP. */
  def write(offset: Int, data: Long, strb: Int = 0xf): Int = {
    liteAddrNow = set(io.liteAddr, BigInt(offset), liteAddrNow)
    liteWNow = set(io.liteWData, (BigInt(strb) << 32) | BigInt(data & 0xffffffffL), liteWNow)
    liteAw = true; liteW = true
    while (liteAw || liteW) {
      val f = step()
      if (f.testBit(SystemSimTop.outFields.indexOf("lite_awready"))) liteAw = false
      if (f.testBit(SystemSimTop.outFields.indexOf("lite_wready"))) liteW = false
    }
    liteBReady = true
    waitFor("write response")(flag("lite_bvalid"))
    val resp = io.liteB.peek().litValue.toInt
    liteBReady = false
    resp
  }
  def write(reg: String, data: Long): Unit = {
    val resp = write(RegisterMap(reg).offset, data)
    assert(resp == 0, s"write $reg: BRESP $resp")
  }

  /** An AXI4-Lite read; returns (data, RRESP). */
  def readResp(offset: Int): (Long, Int) = {
    liteAddrNow = set(io.liteAddr, BigInt(offset), liteAddrNow)
    liteAr = true
    while (liteAr) { if (step().testBit(SystemSimTop.outFields.indexOf("lite_arready"))) liteAr = false }
    liteRReady = true
    waitFor("read data")(flag("lite_rvalid"))
    val r = io.liteR.peek().litValue
    step() // the R handshake
    liteRReady = false
    ((r & 0xffffffffL).toLong, (r >> 32).toInt)
  }
  def read(reg: String): Long = {
    val (d, resp) = readResp(RegisterMap(reg).offset)
    assert(resp == 0, s"read $reg: RRESP $resp")
    d
  }
  def read64(counter: String): BigInt = { val lo = read(s"${counter}_LO"); (BigInt(read(s"${counter}_HI")) << 32) | lo }
  def status(field: String): Boolean = ((read("STATUS") >> RegisterMap.field("STATUS", field).lsb) & 1) == 1

  /** Steps until `interrupt` is high (failing after `limit` cycles); `tick` every 2^12 cycles. */
  def awaitInterrupt(limit: Long, tick: () => Unit = () => ()): Unit = {
    val start = cycle
    while (!flag("interrupt")) {
      step()
      if (cycle - start > limit) throw new AssertionError(s"no interrupt within $limit cycles (cycle $cycle)")
      if ((cycle & 0xfff) == 0) tick()
    }
  }

  def put(at: Long, bytes: Array[Byte]): Unit = mem.write(at, bytes)
  def putRays(at: Long, rays: Seq[RayRecord], flags: Int => Int = _ => 0): Unit = {
    val buf = new Array[Byte](SystemConfig.RayBytes * rays.size)
    val b = ByteBuffer.wrap(buf).order(ByteOrder.LITTLE_ENDIAN)
    for ((r, i) <- rays.zipWithIndex) {
      val o = SystemConfig.RayBytes * i
      for ((w, k) <- (r.origin ++ r.dir ++ Seq(r.tmin, r.tmax)).zipWithIndex) b.putInt(o + 4 * k, w.toInt)
      b.putInt(o + 32, (if (r.shadow) 1 else 0) | flags(i))
      for (k <- 36 until 48 by 4) b.putInt(o + k, 0)
    }
    mem.write(at, buf)
  }

  /** Hit record i of the buffer at `at`: (its number word, the hit, the reserved words). */
  def hitRecord(at: Long, i: Int): (HitRecord, Long) = {
    val b =
      ByteBuffer.wrap(mem.read(at + SystemConfig.HitBytes * i, SystemConfig.HitBytes)).order(ByteOrder.LITTLE_ENDIAN)
    val o = 0
    def u(k: Int) = b.getInt(o + k).toLong & 0xffffffffL
    val status = u(4)
    (
      HitRecord(u(0), (status & 1) == 1, u(8), u(12), u(16), u(20), ((status >> 8) & 0xff).toInt),
      u(24) | u(28) | (status & 0xfe) | (status >> 13)
    )
  }

  /** The driver sequence: load the scene image at `sceneBase`, wait for IRQ SCENE; returns SCENE_ERROR_CODE. */
  def loadScene(sceneBase: Long, limit: Long = 200000): Long = {
    write("IRQ_ENABLE", 3)
    write("SCENE_BASE", sceneBase)
    write("CTRL", 1L << RegisterMap.field("CTRL", "LOAD_SCENE").lsb)
    awaitInterrupt(limit)
    val irq = read("IRQ_STATUS")
    assert((irq & 2) != 0, s"interrupt without IRQ_STATUS.SCENE (IRQ_STATUS $irq)")
    write("IRQ_STATUS", 2)
    assert((read("IRQ_STATUS") & 2) == 0, "IRQ_STATUS.SCENE not cleared by writing 1")
    read("SCENE_ERROR_CODE")
  }

  /** The driver sequence for a batch: registers, START, interrupt, clear it. `progress`: hit records written so far. */
  def runBatch(rayBase: Long, count: Int, hitBase: Long, limit: Long, progress: Long => Unit = _ => ()): Long = {
    write("RAY_BASE", rayBase); write("RAY_COUNT", count); write("HIT_BASE", hitBase)
    write("IRQ_ENABLE", 1)
    val t0 = cycle
    val w0 = writesAnswered
    write("CTRL", 1L << RegisterMap.field("CTRL", "START").lsb)
    awaitInterrupt(limit, () => progress(writesAnswered - w0))
    val t = cycle - t0
    assert((read("IRQ_STATUS") & 1) == 1, "interrupt without IRQ_STATUS.DONE")
    write("IRQ_STATUS", 1)
    assert(read("IRQ_STATUS") == 0, "IRQ_STATUS.DONE not cleared by writing 1")
    assert(status("DONE") && !status("BUSY"), "STATUS after the interrupt: DONE and not BUSY expected")
    t
  }
}

object SystemHarness {

  /** A memory layout: scene at 64 KB, rays and hits after it on 4 KB pages plus `skew` 64-byte lines. */
  final case class Layout(sceneBase: Long, rayBase: Long, hitBase: Long)
  def layout(img: MemoryImage, rays: Int, skew: Int): Layout = {
    def page(x: Long) = (x + 4095) / 4096 * 4096
    val scene = 0x10000L
    val rayBase = page(scene + img.bytes.length) + 64L * skew
    val hitBase = page(rayBase + SystemConfig.RayBytes * rays + 256) + 64L * skew
    Layout(scene, rayBase, hitBase)
  }
}
