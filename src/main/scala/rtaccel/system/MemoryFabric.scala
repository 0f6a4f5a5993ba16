package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Addr, Axi4Master}
import rtaccel.mem.{MemPort, MemPortParams}

/** The memory side of the system: N read clients and one write client onto
  * one AXI4 master, with the on-chip node store in front of DRAM for the node
  * clients (docs/node-store.md).
  *
  * Reads: a node client's request that the store holds is served on chip
  * (NodeStore); every other request goes, round-robin over the clients, to
  * the ReadEngine, which reads the record's bytes in INCR bursts of full beats
  * split at 4 KB, one AXI ID per outstanding record (at most `readSlots`
  * records outstanding, IDs 0 .. readSlots-1), and returns it reassembled
  * with the client's tag, in any order. ID 2^idBits - 1 is the store's fill.
  * A client that holds off `resp.ready` stalls only its own responses.
  *
  * Writes: 32-byte records, one single-beat burst each with strobes on the
  * record's half (WriteEngine); `writesDone` counts B responses.
  *
  * `axiError` is sticky: a non-OKAY rresp or bresp, or a slave breaking the
  * protocol (an R beat for no outstanding request, a wrong rlast), or an
  * internal queue found full (never expected).
  *
  * @param readers     each read client's port (records of any size up to 4 KB, any alignment)
  * @param nodeClients which readers are node readers (served by the node store); all of one record size
  */
class MemoryFabric(sys: SystemConfig, readers: Seq[MemPortParams], nodeClients: Seq[Boolean]) extends Module {
  require(readers.nonEmpty, "MemoryFabric: needs at least one read client")
  require(readers.size == nodeClients.size, s"MemoryFabric: ${readers.size} readers but ${nodeClients.size} nodeClients flags")
  require(readers.forall(_.addrBits <= sys.axiAddrBits), s"MemoryFabric: a reader's address is wider than ${sys.axiAddrBits} bits")
  private val p = sys.axi
  private val nodeIdx = nodeClients.zipWithIndex.collect { case (true, i) => i }
  require(nodeIdx.map(readers(_).recordBytes).distinct.size <= 1, "MemoryFabric: node clients of different record sizes")
  private val fillId = (1 << p.idBits) - 1
  /** Records outstanding at once: every AXI ID but the fill's. */
  val readSlots: Int = fillId
  require(readSlots >= 1, s"MemoryFabric: ${p.idBits} ID bits leave no read ID beside the store fill")

  private val ports = readers
  val io = IO(new Bundle {
    val readers    = Flipped(MixedVec(ports.map(r => new MemPort(r))))
    val write      = Flipped(Decoupled(new WriteRecord(sys)))
    val writesDone = Output(UInt(32.W))
    val store      = new NodeStoreLoad(sys)
    val axi        = new Axi4Master(p)
    val stats      = Output(new FabricStats)
    val axiError   = Output(Bool())
  })
  override def desiredName = s"MemoryFabric_r${readers.size}_id${p.idBits}_ns${sys.nodeStoreBytes / 1024}k"

  private val tagBits = readers.map(_.tagBits).max
  private val engine  = Module(new ReadEngine(p, readers.map(_.recordBytes), tagBits, readSlots))
  private val store   = Option.when(nodeIdx.nonEmpty && sys.nodeStoreBytes > 0)(
    Module(new NodeStore(p, readers(nodeIdx.head).copy(addrBits = p.addrBits), nodeIdx.size, sys.nodeStoreBytes, fillId)))
  private val writer  = Module(new WriteEngine(p))

  // ---- Requests: node-store hits aside, the rest round-robin to the engine ----
  private val arb = Module(new RRArbiter(new ReadReq(p.addrBits, log2Ceil(readers.size).max(1), tagBits), readers.size))
  private val toStore = Wire(Vec(readers.size, Bool()))
  for ((r, i) <- io.readers.zipWithIndex) {
    val k   = nodeIdx.indexOf(i)
    val hit = store.filter(_ => k >= 0).map { s =>
      s.io.probe(k) := r.req.bits.addr
      s.io.req(k).valid     := r.req.valid && s.io.hit(k)
      s.io.req(k).bits.addr := r.req.bits.addr
      s.io.req(k).bits.tag  := r.req.bits.tag
      s.io.hit(k)
    }.getOrElse(false.B)
    toStore(i) := hit
    arb.io.in(i).valid       := r.req.valid && !hit
    arb.io.in(i).bits.addr   := r.req.bits.addr
    arb.io.in(i).bits.client := i.U
    arb.io.in(i).bits.tag    := r.req.bits.tag
    r.req.ready := Mux(hit, store.map(_.io.req(k.max(0)).ready).getOrElse(false.B), arb.io.in(i).ready)

    // Responses: the engine's and the store's, round-robin.
    store.filter(_ => k >= 0) match {
      case Some(s) =>
        val merge = Module(new RRArbiter(chiselTypeOf(r.resp.bits), 2))
        merge.io.in(0).valid := engine.io.resp(i).valid
        merge.io.in(0).bits.data := engine.io.resp(i).bits.data
        merge.io.in(0).bits.tag  := engine.io.resp(i).bits.tag
        engine.io.resp(i).ready  := merge.io.in(0).ready
        merge.io.in(1) <> s.io.resp(k)
        r.resp <> merge.io.out
      case None =>
        r.resp.valid     := engine.io.resp(i).valid
        r.resp.bits.data := engine.io.resp(i).bits.data
        r.resp.bits.tag  := engine.io.resp(i).bits.tag
        engine.io.resp(i).ready := r.resp.ready
    }
  }
  engine.io.req <> arb.io.out

  // ---- AR: the engine's bursts and the store's fill, through a queue so the payload holds while arvalid waits ----
  private val arArb = Module(new RRArbiter(new Axi4Addr(p), 2))
  arArb.io.in(0) <> engine.io.ar
  store match {
    case Some(s) => arArb.io.in(1) <> s.io.ar
    case None    => arArb.io.in(1).valid := false.B; arArb.io.in(1).bits := DontCare
  }
  io.axi.ar <> Queue(arArb.io.out, 2)

  // ---- R: always taken; the fill's ID goes to the store ----
  io.axi.r.ready := true.B
  private val isFill = io.axi.r.bits.id === fillId.U
  engine.io.r.valid := io.axi.r.valid && !isFill
  engine.io.r.bits  := io.axi.r.bits
  store match {
    case Some(s) =>
      s.io.r.valid := io.axi.r.valid && isFill
      s.io.r.bits  := io.axi.r.bits
      s.io.load <> io.store
    case None =>
      // No store: a load is done at once and holds nothing.
      val doneReg = RegInit(false.B)
      when(io.store.start) { doneReg := true.B }
      io.store.busy        := false.B
      io.store.done        := doneReg
      io.store.storedBytes := 0.U
  }
  private val strayFill = store.isEmpty.B && io.axi.r.valid && isFill

  // ---- Writes ----
  writer.io.write.valid     := io.write.valid
  writer.io.write.bits.addr := io.write.bits.addr
  writer.io.write.bits.data := io.write.bits.data
  io.write.ready := writer.io.write.ready
  io.axi.aw <> writer.io.aw
  io.axi.w  <> writer.io.w
  writer.io.b <> io.axi.b
  io.writesDone := writer.io.writesDone

  // ---- Counters and errors ----
  private def counter(inc: Bool): UInt = {
    val c = RegInit(0.U(64.W))
    when(inc) { c := c + 1.U }
    c
  }
  io.stats.readBeats       := counter(io.axi.r.fire)
  io.stats.writeBeats      := counter(io.axi.w.fire)
  io.stats.arStallCycles   := counter(io.axi.ar.valid && !io.axi.ar.ready)
  io.stats.nodeStoreHits   := countBy(PopCount(nodeIdx.map(i => io.readers(i).req.fire && toStore(i))))
  io.stats.nodeStoreMisses := countBy(PopCount(nodeIdx.map(i => io.readers(i).req.fire && !toStore(i))))
  private def countBy(n: UInt): UInt = {
    val c = RegInit(0.U(64.W))
    c := c + n
    c
  }
  private val strayReg = RegInit(false.B)
  when(strayFill) { strayReg := true.B }
  io.axiError := engine.io.error || writer.io.error || store.map(_.io.error).getOrElse(false.B) || strayReg
}
