package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Addr, Axi4Params, Axi4R, BurstMath}
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
  private val lineBits  = log2Ceil(lines + 1)

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
  when(startNow) {
    // Whole words (a node never straddles the end), at most the capacity.
    val wanted = (io.load.bytes +& (wordBytes - 1).U) >> log2Ceil(wordBytes)
    val ws     = Mux(wanted > words.U, words.U, wanted)
    baseReg     := io.load.base
    totalReg    := ws << log2Ceil(lanes)
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
    fillAddrReg := io.load.base
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
  io.load.storedBytes := Mux(loadedReg, totalReg << beatBits, 0.U)
  io.error            := errorReg

  // ---- Serve ----
  private val storedBytes = totalReg << beatBits
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
  private val wWord   = if (lanes == 1) wLineReg else wLineReg >> log2Ceil(lanes)
  private val wMask   = VecInit((0 until lanes).map(l => if (lanes == 1) true.B else wLineReg(log2Ceil(lanes) - 1, 0) === l.U))
  private val wData   = VecInit(Seq.fill(lanes)(wDataReg))

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
    val rdata = if (c % 2 == 0) mem.readWrite(Mux(wValidReg, wWord, word), wData, wMask, wValidReg || fire, wValidReg)
                else mem.read(word, fire)
    // A hit is only accepted when loaded, and the fill writes only while not loaded.
    when(fire && wValidReg) { errorReg := true.B }
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
  /** Output queue per client: the read in the pipeline + 1 more than it takes to see a dequeue, so a client that always takes keeps one per cycle. */
  val OutDepth: Int = Latency + 1
}
