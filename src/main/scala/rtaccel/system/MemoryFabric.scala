package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.{PerfCounter, RoundRobinArbiter}
import rtaccel.axi.{Axi4Addr, Axi4Master}
import rtaccel.mem.{MemPort, MemPortParams}

/** The memory side of the system: N read clients and one write client onto
  * one AXI4 master, with the on-chip node store in front of DRAM for the node
  * clients (docs/node-store.md) and the on-chip triangle store in front of
  * it for the triangle clients (docs/scene-store.md).
  *
  * Reads: a node client's request that the node store holds is served on
  * chip (NodeStore), a triangle client's that the triangle store holds too
  * (TriStore); every other request goes, round-robin over the clients, to
  * the ReadEngine, which reads the record's bytes in INCR bursts of full beats
  * split at 4 KB, one AXI ID per outstanding record (at most `readSlots`
  * records outstanding, IDs 0 .. readSlots-1), and returns it reassembled
  * with the client's tag, in any order. ID 2^idBits - 1 is the stores' fill:
  * the scene loader fills the node store, then the triangle store, never
  * both at once, so its R beats go to the node store while that one is
  * busy and to the triangle store otherwise (which flags a beat it did not
  * ask for).
  * A client that holds off `resp.ready` stalls only its own responses.
  *
  * Writes: 64-byte lines of one or two 32-byte records, one single-beat burst
  * each with strobes on the records it carries (WriteEngine); `writesDone`
  * counts the records of the writes whose B response has come.
  *
  * `axiError` is sticky: a non-OKAY rresp or bresp, or a slave breaking the
  * protocol (an R beat for no outstanding request, a wrong rlast), or an
  * internal queue found full (never expected).
  *
  * @param readers     each read client's port (records of any size up to 4 KB, any alignment)
  * @param nodeClients which readers are node readers (served by the node store); all of one record size
  * @param triClients  which readers are triangle readers (served by the triangle store); all of one record size;
  *                    empty: none
  */
class MemoryFabric(
    sys: SystemConfig,
    readers: Seq[MemPortParams],
    nodeClients: Seq[Boolean],
    triClients: Seq[Boolean] = Nil
) extends Module {
  require(readers.nonEmpty, "MemoryFabric: needs at least one read client")
  require(
    readers.size == nodeClients.size,
    s"MemoryFabric: ${readers.size} readers but ${nodeClients.size} nodeClients flags"
  )
  require(
    readers.forall(_.addrBits <= sys.axiAddrBits),
    s"MemoryFabric: a reader's address is wider than ${sys.axiAddrBits} bits"
  )
  private val p = sys.axi
  require(
    triClients.isEmpty || triClients.size == readers.size,
    s"MemoryFabric: ${readers.size} readers but ${triClients.size} triClients flags"
  )
  private val nodeIdx = nodeClients.zipWithIndex.collect { case (true, i) => i }
  private val triIdx = triClients.zipWithIndex.collect { case (true, i) => i }
  require(
    nodeIdx.map(readers(_).recordBytes).distinct.size <= 1,
    "MemoryFabric: node clients of different record sizes"
  )
  require(
    triIdx.map(readers(_).recordBytes).distinct.size <= 1,
    "MemoryFabric: triangle clients of different record sizes"
  )
  require(nodeIdx.intersect(triIdx).isEmpty, "MemoryFabric: a client is both a node and a triangle client")
  private val fillId = (1 << p.idBits) - 1

  /** Records outstanding at once: every AXI ID but the fill's. */
  val readSlots: Int = fillId
  require(readSlots >= 2, s"MemoryFabric: ${p.idBits} ID bits leave fewer than two read IDs beside the store fill")

  private val ports = readers
  val io = IO(new Bundle {
    val readers = Flipped(MixedVec(ports.map(r => new MemPort(r))))
    val write = Flipped(Decoupled(new WriteRecord(sys)))
    val writesDone = Output(UInt(32.W))
    val store = new NodeStoreLoad(sys)
    val triStore = new NodeStoreLoad(sys)
    val axi = new Axi4Master(p)
    val stats = Output(new FabricStats)
    val axiError = Output(Bool())
  })
  override def desiredName = s"MemoryFabric_r${readers.size}_id${p.idBits}_ns${sys.nodeStoreBytes / 1024}k" +
    (if (triIdx.nonEmpty && sys.triStoreBytes > 0) s"_ts${sys.triStoreBytes / 1024}k" else "")

  private val tagBits = readers.map(_.tagBits).max
  private val engine = Module(new ReadEngine(p, readers.map(_.recordBytes), tagBits, readSlots))

  /** A store for the clients `idx` (none without clients or bytes): their port, count and copies, then `make`. */
  private def storeFor[S <: Module](idx: Seq[Int], bytes: Int)(make: (MemPortParams, Int, Int) => S): Option[S] =
    Option.when(idx.nonEmpty && bytes > 0)(
      Module(make(readers(idx.head).copy(addrBits = p.addrBits), idx.size, sys.storeCopiesFor(idx.size)))
    )
  private val store = storeFor(nodeIdx, sys.nodeStoreBytes)((port, n, copies) =>
    new NodeStore(p, port, n, sys.nodeStoreBytes, fillId, copies)
  )
  private val triStore = storeFor(triIdx, sys.triStoreBytes)((port, n, copies) =>
    new TriStore(p, port, n, sys.triStoreBytes, fillId, copies)
  )
  private val writer = Module(new WriteEngine(p))

  /** An on-chip store's client side: probe, hit, request and response of client k. */
  private class Served(
      val probe: Vec[UInt],
      val hit: Vec[Bool],
      val req: Vec[DecoupledIO[rtaccel.mem.MemRequest]],
      val resp: Vec[DecoupledIO[rtaccel.mem.MemResponse]]
  )
  private val served: Seq[Option[(Served, Int)]] = readers.indices.map { i =>
    store.filter(_ => nodeIdx.contains(i)).map(s =>
      (new Served(s.io.probe, s.io.hit, s.io.req, s.io.resp), nodeIdx.indexOf(i))
    )
      .orElse(triStore.filter(_ => triIdx.contains(i)).map(s =>
        (new Served(s.io.probe, s.io.hit, s.io.req, s.io.resp), triIdx.indexOf(i))
      ))
  }

  // ---- Requests: store hits aside, the rest round-robin to the engine ----
  private val clientBits = log2Ceil(readers.size).max(1)
  // Each client's DRAM request (its store misses), into the clients' round-robin arbiter.
  private val dramReqs = Wire(Vec(readers.size, Decoupled(new ReadReq(p.addrBits, clientBits, tagBits))))
  private val granted: DecoupledIO[ReadReq] =
    if (readers.size <= MemoryFabric.DirectGrantClients) {
      val arb = Module(new RoundRobinArbiter(new ReadReq(p.addrBits, clientBits, tagBits), readers.size))
      arb.io.in <> dramReqs
      arb.io.out
    } else {
      // With more clients the grant lands in a register (one-hot, `grantOHReg`) and the granted client's request in
      // that client's own register (`reqRegs`, loaded by its own grant bit): no select follows the grant in its
      // cycle. The next cycle selects the granted request (an AND-OR of the request registers by the one-hot grant).
      // The grant and the request fields' select in one cycle were the fabric's longest path with 6 and 8 clients,
      // 5.24 and 5.53 ns (docs/fmax.md). A new grant is made only while the grant stage is empty or hands its
      // request on in this cycle, so no granted request is overwritten: each is handed on once, when it is taken
      // (valid/ready). The arbiter grants only: the granted request is taken into its client's register beside it.
      val arb = Module(new RoundRobinArbiter(UInt(1.W), readers.size))
      val out = Wire(Decoupled(new ReadReq(p.addrBits, clientBits, tagBits)))
      val grantValidReg = RegInit(false.B)
      val grantOHReg = RegInit(0.U(readers.size.W))
      val reqRegs = Reg(Vec(readers.size, new ReadReq(p.addrBits, clientBits, tagBits)))
      for ((q, i) <- dramReqs.zipWithIndex) {
        arb.io.in(i).valid := q.valid
        arb.io.in(i).bits := 0.U
        q.ready := arb.io.in(i).ready
        when(arb.io.in(i).fire) { reqRegs(i) := q.bits }
      }
      val grantRoom = !grantValidReg || out.ready
      arb.io.out.ready := grantRoom
      when(grantRoom) {
        grantValidReg := arb.io.out.valid
        grantOHReg := VecInit(arb.io.in.map(_.fire)).asUInt
      }
      out.valid := grantValidReg
      out.bits.addr := Mux1H(grantOHReg, reqRegs.map(_.addr))
      out.bits.tag := Mux1H(grantOHReg, reqRegs.map(_.tag))
      out.bits.client := OHToUInt(grantOHReg)
      out
    }
  // A two-entry slice (one request a cycle) between the clients' arbiter and the engine: the arbiter's choice,
  // the request fields' select and the engine's beat count and ready were one path, the fabric's longest
  // (docs/fmax.md). A read pays one cycle for it, and one more for the registered grant with more than
  // `DirectGrantClients` clients (MemoryFabric.requestStages); a store hit passes neither.
  engine.io.req <> Queue(granted, 2)
  private val toStore = Wire(Vec(readers.size, Bool()))
  for ((r, i) <- io.readers.zipWithIndex) {
    val hit = served(i).map { case (s, k) =>
      s.probe(k) := r.req.bits.addr
      s.req(k).valid := r.req.valid && s.hit(k)
      s.req(k).bits.addr := r.req.bits.addr
      s.req(k).bits.tag := r.req.bits.tag
      s.hit(k)
    }.getOrElse(false.B)
    toStore(i) := hit
    dramReqs(i).valid := r.req.valid && !hit
    dramReqs(i).bits.addr := r.req.bits.addr
    dramReqs(i).bits.client := i.U
    dramReqs(i).bits.tag := r.req.bits.tag
    r.req.ready := Mux(hit, served(i).map { case (s, k) => s.req(k).ready }.getOrElse(false.B), dramReqs(i).ready)

    // Responses: the engine's and the store's, round-robin.
    served(i) match {
      case Some((s, k)) =>
        val merge = Module(new RRArbiter(chiselTypeOf(r.resp.bits), 2))
        merge.io.in(0).valid := engine.io.resp(i).valid
        merge.io.in(0).bits.data := engine.io.resp(i).bits.data
        merge.io.in(0).bits.tag := engine.io.resp(i).bits.tag
        engine.io.resp(i).ready := merge.io.in(0).ready
        merge.io.in(1) <> s.resp(k)
        r.resp <> merge.io.out
      case None =>
        r.resp.valid := engine.io.resp(i).valid
        r.resp.bits.data := engine.io.resp(i).bits.data
        r.resp.bits.tag := engine.io.resp(i).bits.tag
        engine.io.resp(i).ready := r.resp.ready
    }
  }

  // ---- AR: the engine's bursts and the stores' fills, through a queue so the payload holds while arvalid waits ----
  private val fills = store.map(_.io.ar).toSeq ++ triStore.map(_.io.ar)
  private val arArb = Module(new RRArbiter(new Axi4Addr(p), 1 + fills.size))
  arArb.io.in(0) <> engine.io.ar
  for ((f, j) <- fills.zipWithIndex) arArb.io.in(1 + j) <> f
  io.axi.ar <> Queue(arArb.io.out, 2)

  // ---- R: always taken; the fill's ID goes to the node store while it fills, else to the triangle store ----
  io.axi.r.ready := true.B
  private val isFill = io.axi.r.bits.id === fillId.U
  engine.io.r.valid := io.axi.r.valid && !isFill
  engine.io.r.bits := io.axi.r.bits
  private val nodeFilling = store.map(_.io.load.busy).getOrElse(false.B)

  /** A store's load side; with no store, a load is done at once and holds nothing. */
  private def connectLoad(load: NodeStoreLoad, s: Option[NodeStoreLoad]): Unit = s match {
    case Some(l) => l <> load
    case None =>
      val doneReg = RegInit(false.B)
      when(load.start) { doneReg := true.B }
      load.busy := false.B
      load.done := doneReg
      load.storedBytes := 0.U
  }
  connectLoad(io.store, store.map(_.io.load))
  connectLoad(io.triStore, triStore.map(_.io.load))
  store.foreach { s =>
    s.io.r.valid := io.axi.r.valid && isFill && (nodeFilling || triStore.isEmpty.B)
    s.io.r.bits := io.axi.r.bits
  }
  triStore.foreach { s =>
    s.io.r.valid := io.axi.r.valid && isFill && !nodeFilling
    s.io.r.bits := io.axi.r.bits
  }
  private val strayFill = (store.isEmpty && triStore.isEmpty).B && io.axi.r.valid && isFill

  // ---- Writes ----
  writer.io.write.valid := io.write.valid
  writer.io.write.bits.addr := io.write.bits.addr
  writer.io.write.bits.data := io.write.bits.data
  writer.io.write.bits.halves := io.write.bits.halves
  io.write.ready := writer.io.write.ready
  io.axi.aw <> writer.io.aw
  io.axi.w <> writer.io.w
  writer.io.b <> io.axi.b
  io.writesDone := writer.io.writesDone

  // ---- Counters and errors ----
  io.stats.readBeats := PerfCounter(io.axi.r.fire.asUInt)
  io.stats.writeBeats := PerfCounter(io.axi.w.fire.asUInt)
  io.stats.arStallCycles := PerfCounter((io.axi.ar.valid && !io.axi.ar.ready).asUInt)
  // The events are registered before they are counted, and their count is registered before it is added: a
  // request's handshake comes through the clients' grant, and that chain ending in the events' count or the
  // count's add was the fabric's longest path (docs/fmax.md). The counts run two cycles behind.
  private def counted(events: Seq[Bool]): UInt = {
    val fired = if (events.isEmpty) Seq(false.B) else events
    val firedReg = RegInit(0.U(fired.size.W))
    firedReg := VecInit(fired).asUInt
    val eventsReg = RegInit(0.U(log2Ceil(fired.size + 1).W))
    eventsReg := PopCount(firedReg)
    PerfCounter(eventsReg)
  }
  io.stats.nodeStoreHits := counted(nodeIdx.map(i => io.readers(i).req.fire && toStore(i)))
  io.stats.nodeStoreMisses := counted(nodeIdx.map(i => io.readers(i).req.fire && !toStore(i)))
  io.stats.triStoreHits := counted(triIdx.map(i => io.readers(i).req.fire && toStore(i)))
  private val strayReg = RegInit(false.B)
  when(strayFill) { strayReg := true.B }
  io.axiError := engine.io.error || writer.io.error || store.map(_.io.error).getOrElse(false.B) ||
    triStore.map(_.io.error).getOrElse(false.B) || strayReg
}

object MemoryFabric {

  /** Clients up to which the clients' round-robin grant and the request's select into the slice are one cycle (four:
    * one core's, as in the formal system); with more (two cores and up), the grant is registered first: at six
    * clients the one cycle was 5.24 ns, at eight 5.53 ns (docs/fmax.md). */
  val DirectGrantClients = 4

  /** Cycles a DRAM read spends between the clients' arbiter and the read engine: the slice, and the grant register
    * with more than [[DirectGrantClients]] clients. */
  def requestStages(clients: Int): Int = if (clients > DirectGrantClients) 2 else 1
}
