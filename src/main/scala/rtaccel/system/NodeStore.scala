package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Addr, Axi4Params, Axi4R, BurstMath, ByteRotate}
import rtaccel.mem.{MemPortParams, MemRequest, MemResponse}

/** The on-chip node store: the first `capacityBytes` bytes of the node array
  * (the top of the tree when nodes are in top-levels-first order, see
  * docs/node-store.md), copied from DRAM when a scene is loaded, then served
  * from block RAM at a fixed latency to `clients` node clients.
  *
  * Storage: words of max(record, beat) bytes, written a beat (one masked
  * lane) at a time by the fill. Each copy of the storage is a true dual-port
  * BRAM serving two clients (port A also takes the fill's writes, which only
  * happen while no client can hit); `clients` > 2 gets ceil(clients / 2)
  * copies.
  *
  * Fill: bursts of up to `FillBurstBeats` beats with AXI ID `fillId`, never
  * crossing 4 KB, at most `FillBursts` outstanding (a bound so the fill
  * cannot flood the slave's queues; 8 x 16 beats cover DRAM latency). Beats
  * of one ID arrive in order, so a line counter places them.
  *
  * A beat wider than the base's 64-byte alignment (a 1024-bit m_axi: the
  * image's node array starts at offset 64) is read from the beat-aligned
  * address below `base`: with `off` = base mod beat, line j (store bytes
  * j*B ..) is beat j's bytes from `off` on, then beat j+1's first `off`
  * bytes, so each beat, rotated right by `off`, completes the line before
  * it, one extra beat at the end. Every write is still one whole line, so
  * the storage maps to block RAM as before. A base that is not 64-byte
  * aligned sets `error` (the contract's alignment).
  *
  * A request hits when the store is loaded, its address is record-aligned
  * relative to `base`, and lies below base + storedBytes. Latency: request
  * accepted in cycle t, response offered from t + `NodeStore.Latency` = 2
  * (the BRAM read, then the output queue). Full rate: one record per client per
  * cycle.
  */
class NodeStore(p: Axi4Params, port: MemPortParams, clients: Int, capacityBytes: Int, fillId: Int) extends Module {
  private val B         = p.beatBytes
  private val beatBits  = log2Ceil(B)
  private val recBytes  = port.recordBytes
  require(Integer.bitCount(recBytes) == 1, s"NodeStore: node records must be a power of two bytes, got $recBytes")
  private val wordBytes = recBytes.max(B)
  private val lanes     = wordBytes / B
  require(capacityBytes > 0 && capacityBytes % wordBytes == 0, s"NodeStore: capacity $capacityBytes is not a positive multiple of $wordBytes bytes")
  private val words     = capacityBytes / wordBytes
  private val lines     = capacityBytes / B
  /** The beat is wider than the base's alignment: the fill reads one beat more and realigns (above). */
  private val realign   = B > NodeStore.BaseAlign
  /** Counts of beats: the lines, and the realigning fill's extra beat. */
  private val lineBits  = log2Ceil(lines + (if (realign) 2 else 1))

  val io = IO(new Bundle {
    val load  = new NodeStoreLoad(p.addrBits)
    /** Would a request at this address hit? (combinational, per client) */
    val probe = Input(Vec(clients, UInt(p.addrBits.W)))
    val hit   = Output(Vec(clients, Bool()))
    val req   = Vec(clients, Flipped(Decoupled(new MemRequest(port))))
    val resp  = Vec(clients, Decoupled(new MemResponse(port)))
    val ar    = Decoupled(new Axi4Addr(p))
    /** R beats with ID `fillId`; always taken. */
    val r     = Flipped(Valid(new Axi4R(p)))
    val error = Output(Bool())
  })

  // ---- Fill ----
  private val baseReg     = RegInit(0.U(p.addrBits.W))
  private val totalReg    = RegInit(0.U(lineBits.W)) // lines to fill
  private val issuedReg   = RegInit(0.U(lineBits.W))
  private val receivedReg = RegInit(0.U(lineBits.W))
  private val burstsReg   = RegInit(0.U(log2Ceil(NodeStore.FillBursts + 1).W))
  private val busyReg     = RegInit(false.B)
  private val loadedReg   = RegInit(false.B)
  private val errorReg    = RegInit(false.B)
  // A start while a fill runs is ignored: beats of its bursts are still on the way.
  private val startNow = io.load.start && !busyReg
  // The base's offset in its beat, in whole 64-byte lines (0 unless `realign`).
  private val alignBits = log2Ceil(NodeStore.BaseAlign)
  private val offReg = Option.when(realign)(RegInit(0.U((beatBits - alignBits).W)))
  private val storedLinesReg = Option.when(realign)(RegInit(0.U(lineBits.W)))
  when(startNow) {
    // Whole words (a node never straddles the end), at most the capacity.
    val wanted = (io.load.bytes +& (wordBytes - 1).U) >> log2Ceil(wordBytes)
    val ws     = Mux(wanted > words.U, words.U, wanted)
    baseReg     := io.load.base
    val off     = offReg.map(_ => io.load.base(beatBits - 1, alignBits))
    totalReg    := off.fold(ws << log2Ceil(lanes))(o => (ws << log2Ceil(lanes)) +& (o =/= 0.U).asUInt)
    offReg.zip(off).foreach { case (r, o) => r := o }
    storedLinesReg.foreach(_ := ws << log2Ceil(lanes))
    if (realign) when(io.load.base(alignBits - 1, 0) =/= 0.U) { errorReg := true.B }
    issuedReg   := 0.U
    receivedReg := 0.U
    busyReg     := true.B
    loadedReg   := false.B
  }
  // The next burst is sized a cycle before it is offered, from registers
  // only (its address, the lines left), and waits in arAddrReg/arBeatsReg:
  // the 4 KB room, the two minimums and the counters' adds are not one path
  // (docs/fmax.md). A burst is prepared only while none waits, and counted in
  // burstsReg when it leaves, so at most FillBursts are outstanding as before.
  private val fillAddrReg  = RegInit(0.U(p.addrBits.W)) // the next burst's address: base + issued beats
  private val arPendReg    = RegInit(false.B)
  private val arAddrReg    = Reg(UInt(p.addrBits.W))
  private val arBeatsReg   = Reg(UInt(log2Ceil(NodeStore.FillBurstBeats + 1).W))
  private val left     = totalReg - issuedReg
  private val room     = BurstMath.beatsToBoundary(p, fillAddrReg)
  private val beats    = Seq(left, room, NodeStore.FillBurstBeats.U).reduce((a, b) => Mux(a < b, a, b))
  when(busyReg && !arPendReg && issuedReg =/= totalReg && burstsReg =/= NodeStore.FillBursts.U) {
    arPendReg  := true.B
    arAddrReg  := fillAddrReg
    arBeatsReg := beats
  }
  io.ar.valid := arPendReg
  io.ar.bits  := Axi4Addr.incr(p, fillId.U, arAddrReg, arBeatsReg)
  when(io.ar.fire) {
    arPendReg   := false.B
    issuedReg   := issuedReg + arBeatsReg
    fillAddrReg := fillAddrReg + (arBeatsReg << beatBits)
  }
  when(startNow) {
    fillAddrReg := (if (realign) Cat(io.load.base(p.addrBits - 1, beatBits), 0.U(beatBits.W)) else io.load.base)
    arPendReg   := false.B
  }
  private val beatOk = busyReg && receivedReg =/= issuedReg && io.r.bits.resp === 0.U
  when(io.r.valid && !beatOk) { errorReg := true.B }
  private val fillWrite = io.r.valid && beatOk
  burstsReg := burstsReg + io.ar.fire.asUInt - (fillWrite && io.r.bits.last).asUInt
  when(fillWrite) { receivedReg := receivedReg + 1.U }
  when(busyReg && receivedReg === totalReg) {
    busyReg   := false.B
    loadedReg := true.B
  }
  // Stage the beat: the write happens the cycle after it arrives.
  private val wValidReg = RegNext(fillWrite, false.B)
  private val wLineReg  = RegEnable(receivedReg, fillWrite)
  private val wDataReg  = RegEnable(io.r.bits.data, fillWrite)
  io.load.busy        := busyReg
  io.load.done        := loadedReg
  // Lines held: the beats read, but the realigning fill's extra one.
  private val storedBytes = storedLinesReg.getOrElse(totalReg) << beatBits
  io.load.storedBytes := Mux(loadedReg, storedBytes, 0.U)
  io.error            := errorReg

  // ---- Serve ----
  // The end of the stored bytes, registered: it follows baseReg and totalReg a
  // cycle late, and a hit needs loadedReg, set only when the fill is done, many
  // cycles after both were loaded. So the hit test is two compares side by
  // side (and the low bits' equality), not a subtraction then a compare.
  private val limitReg = RegNext(baseReg +& storedBytes, 0.U)
  private val recBits  = log2Ceil(recBytes)
  for (c <- 0 until clients) {
    val a = io.probe(c)
    val aligned = if (recBits == 0) true.B else a(recBits - 1, 0) === baseReg(recBits - 1, 0)
    io.hit(c) := loadedReg && !startNow && a >= baseReg && a < limitReg && aligned
  }
  private val copies  = (clients + 1) / 2
  private val mems    = Seq.fill(copies)(SyncReadMem(words, Vec(lanes, UInt((8 * B).W))))
  // The line a staged beat writes and its bytes: the beat itself, or (realigning) the line before it, completed.
  private val (wEnable, wLine, wLineData) = offReg match {
    case None => (wValidReg, wLineReg, wDataReg)
    case Some(off) =>
      val rot     = ByteRotate.right(wDataReg, Cat(off, 0.U(alignBits.W)))
      val prevReg = RegEnable(rot, wValidReg)
      // Bytes below B - off of the line come from the beat before (rotated), the rest from this one.
      val keep    = (0 until B).map(j => Cat(off, 0.U(alignBits.W)) +& j.U < B.U)
      val merged  = Cat((0 until B).reverse.map(j => Mux(keep(j), prevReg(8 * j + 7, 8 * j), rot(8 * j + 7, 8 * j))))
      val shifted = off =/= 0.U
      (wValidReg && !(shifted && wLineReg === 0.U), Mux(shifted, wLineReg - 1.U, wLineReg), Mux(shifted, merged, wDataReg))
  }
  private val wWord   = if (lanes == 1) wLine else wLine >> log2Ceil(lanes)
  private val wMask   = VecInit((0 until lanes).map(l => if (lanes == 1) true.B else wLine(log2Ceil(lanes) - 1, 0) === l.U))
  private val wData   = VecInit(Seq.fill(lanes)(wLineData))

  for (c <- 0 until clients) {
    val mem    = mems(c / 2)
    val outQ   = Module(new Queue(new MemResponse(port), NodeStore.OutDepth))
    val s1ValidReg = RegInit(false.B)
    // Credit: queued + being read < depth, so every read has a place when it lands.
    val credit = outQ.io.count +& s1ValidReg.asUInt < NodeStore.OutDepth.U
    io.req(c).ready := credit
    val fire = io.req(c).fire
    val rel  = io.req(c).bits.addr - baseReg
    val word = rel >> log2Ceil(wordBytes)
    val rdata = if (c % 2 == 0) mem.readWrite(Mux(wEnable, wWord, word), wData, wMask, wEnable || fire, wEnable)
                else mem.read(word, fire)
    // A hit is only accepted when loaded, and the fill writes only while not loaded.
    when(fire && wEnable) { errorReg := true.B }
    s1ValidReg := fire
    val s1TagReg = RegEnable(io.req(c).bits.tag, fire)
    val s1SubReg = RegEnable(rel(log2Ceil(wordBytes) - 1, 0), fire)
    // The read data goes straight into the output queue, with no register of
    // its own: Yosys 0.23 would merge such a register into the memory's read
    // port first and leave the port's address register outside, so the shared
    // read/write port would become a read port and a write port, and the
    // memory would be doubled to give the second client its read port
    // (measured: 456 instead of 228 BRAM36 for 1 MiB). The BRAM's output is
    // the read's register.
    outQ.io.enq.valid     := s1ValidReg
    outQ.io.enq.bits.data := (if (recBytes >= B) rdata.asUInt else (rdata.asUInt >> (s1SubReg << 3))(8 * recBytes - 1, 0))
    outQ.io.enq.bits.tag  := s1TagReg
    when(outQ.io.enq.valid && !outQ.io.enq.ready) { errorReg := true.B }
    io.resp(c) <> outQ.io.deq
  }
}

object NodeStore {
  /** Request to response offered, in cycles: the BRAM read (its address register), then the output queue. */
  val Latency = 2
  val FillBurstBeats = 16
  val FillBursts = 8
  /** The node array's alignment in DDR (NodeStoreLoad: `base` is 64-byte aligned). */
  val BaseAlign = 64
  /** Output queue per client: the read in the pipeline + 1 more than it takes to see a dequeue, so a client that always takes keeps one per cycle. */
  val OutDepth: Int = Latency + 1
}
