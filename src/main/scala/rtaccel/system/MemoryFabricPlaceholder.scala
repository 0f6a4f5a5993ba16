package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.Axi4Master
import rtaccel.mem.{MemPort, MemPortParams}

// PLACEHOLDER for the sys-mem helper's MemoryFabric (system contract): the same
// interface, the simplest behaviour that is correct. Deleted when branch
// sysmem's MemoryFabric is merged.

/** One 32-byte hit record to write at a 32-aligned byte address. */
class WriteRecord(sys: SystemConfig) extends Bundle {
  val addr = UInt(sys.axiAddrBits.W)
  val data = UInt((SystemConfig.HitBytes * 8).W)
}

/** Node store preload, fabric's view: `start` (one-cycle pulse) with the node
  * array's base and size; `done` pulses once when the store holds it.
  */
class NodeStoreLoad(sys: SystemConfig) extends Bundle {
  val start = Input(Bool())
  val base  = Input(UInt(sys.axiAddrBits.W))
  val bytes = Input(UInt(32.W))
  val done  = Output(Bool())
}

class FabricStats extends Bundle {
  val nodeStoreHits   = UInt(64.W)
  val nodeStoreMisses = UInt(64.W)
}

/** A blocking memory side: one read line at a time (len 0, so no burst ever
  * crosses 4 KB), readers served round-robin, one write at a time. No node
  * store: preload `done` follows `start` at once and every node read is a miss.
  */
class MemoryFabric(sys: SystemConfig, readerParams: Seq[MemPortParams], nodeClients: Seq[Boolean]) extends Module {
  private val readers = readerParams
  require(readers.size == nodeClients.size, "MemoryFabric: one nodeClients flag per reader")
  private val maxBytes = readers.map(_.recordBytes).max
  private val maxTag = readers.map(_.tagBits).max
  val io = IO(new Bundle {
    val readers    = Flipped(MixedVec(readerParams.map(p => new MemPort(p))))
    val write      = Flipped(Decoupled(new WriteRecord(sys)))
    val writesDone = Output(UInt(32.W))
    val store      = new NodeStoreLoad(sys)
    val axi        = new Axi4Master(sys)
    val stats      = Output(new FabricStats)
    val axiError   = Output(Bool())
  })

  private val line = sys.axiDataBytes
  private val maxLines = (maxBytes + line - 1) / line + 1 // an unaligned record touches one more line
  private val n = readers.size
  private val srcBits = log2Ceil(n).max(1)

  // ---- reads: pick a client, fetch its record's lines one by one, answer ----
  private val sIdle :: sAddr :: sData :: sResp :: Nil = Enum(4)
  private val stateReg  = RegInit(sIdle)
  private val srcReg    = Reg(UInt(srcBits.W))
  private val addrReg   = Reg(UInt(sys.axiAddrBits.W))
  private val tagReg    = Reg(UInt(maxTag.W))
  private val linesReg  = Reg(UInt(log2Ceil(maxLines + 1).W))
  private val gotReg    = Reg(UInt(log2Ceil(maxLines + 1).W))
  private val bufReg    = Reg(Vec(maxLines, UInt(sys.axiDataBits.W)))
  private val rrReg     = RegInit(0.U(srcBits.W))

  private val valids = VecInit(io.readers.map(_.req.valid))
  private val order = (0 until n).map(k => Mux(rrReg +& k.U >= n.U, rrReg +& k.U - n.U, rrReg +& k.U)(srcBits - 1, 0))
  private val pick = PriorityMux(order.map(valids(_)), order)
  private val reqBytes = VecInit(readers.map(p => p.recordBytes.U(16.W)))
  private val reqAddr = VecInit(io.readers.map(_.req.bits.addr.pad(sys.axiAddrBits)(sys.axiAddrBits - 1, 0)))
  private val reqTag = VecInit(io.readers.map(_.req.bits.tag.pad(maxTag)))
  for ((r, i) <- io.readers.zipWithIndex) r.req.ready := stateReg === sIdle && valids.asUInt.orR && pick === i.U
  when(stateReg === sIdle && valids.asUInt.orR) {
    val a = reqAddr(pick)
    srcReg := pick; addrReg := a; tagReg := reqTag(pick)
    linesReg := ((a(5, 0) +& reqBytes(pick) - 1.U) >> 6) + 1.U
    gotReg := 0.U
    rrReg := Mux(pick === (n - 1).U, 0.U, pick + 1.U)
    stateReg := sAddr
  }
  private val ar = io.axi.ar
  ar.valid := stateReg === sAddr
  ar.bits.id := 0.U; ar.bits.addr := Cat(addrReg(sys.axiAddrBits - 1, 6), 0.U(6.W)) + (gotReg << 6)
  ar.bits.len := 0.U; ar.bits.size := 6.U; ar.bits.burst := 1.U; ar.bits.lock := false.B
  ar.bits.cache := 3.U; ar.bits.prot := 0.U; ar.bits.qos := 0.U
  when(ar.fire) { stateReg := sData }
  io.axi.r.ready := stateReg === sData
  private val errorReg = RegInit(false.B)
  when(io.axi.r.fire) {
    bufReg(gotReg) := io.axi.r.bits.data
    errorReg := errorReg || io.axi.r.bits.resp =/= 0.U
    gotReg := gotReg + 1.U
    stateReg := Mux(gotReg + 1.U === linesReg, sResp, sAddr)
  }
  private val record = (bufReg.asUInt >> Cat(addrReg(5, 0), 0.U(3.W)))(maxBytes * 8 - 1, 0)
  for ((r, i) <- io.readers.zipWithIndex) {
    r.resp.valid := stateReg === sResp && srcReg === i.U
    r.resp.bits.data := record
    r.resp.bits.tag := tagReg
  }
  when(stateReg === sResp && VecInit(io.readers.map(_.resp.ready))(srcReg)) { stateReg := sIdle }

  // ---- writes: one 32-byte record as one beat with its half of the strobes ----
  private val wIdle :: wSend :: wResp :: Nil = Enum(3)
  private val wStateReg = RegInit(wIdle)
  private val wRecReg = Reg(new WriteRecord(sys))
  private val awDoneReg, wDoneReg = RegInit(false.B)
  io.write.ready := wStateReg === wIdle
  when(io.write.fire) { wRecReg := io.write.bits; wStateReg := wSend; awDoneReg := false.B; wDoneReg := false.B }
  private val aw = io.axi.aw
  aw.valid := wStateReg === wSend && !awDoneReg
  aw.bits := ar.bits
  aw.bits.addr := Cat(wRecReg.addr(sys.axiAddrBits - 1, 6), 0.U(6.W))
  private val upper = wRecReg.addr(5)
  io.axi.w.valid := wStateReg === wSend && !wDoneReg
  io.axi.w.bits.data := Mux(upper, Cat(wRecReg.data, 0.U(256.W)), wRecReg.data.pad(512))
  io.axi.w.bits.strb := Mux(upper, "hffffffff00000000".U, "h00000000ffffffff".U)
  io.axi.w.bits.last := true.B
  when(aw.fire) { awDoneReg := true.B }
  when(io.axi.w.fire) { wDoneReg := true.B }
  when(wStateReg === wSend && (awDoneReg || aw.fire) && (wDoneReg || io.axi.w.fire)) { wStateReg := wResp }
  io.axi.b.ready := wStateReg === wResp
  private val writesReg = RegInit(0.U(32.W))
  when(io.axi.b.fire) {
    writesReg := writesReg + 1.U
    errorReg := errorReg || io.axi.b.bits.resp =/= 0.U
    wStateReg := wIdle
  }
  io.writesDone := writesReg
  io.axiError := errorReg

  io.store.done := RegNext(io.store.start, false.B)
  private val nodeReads = RegInit(0.U(64.W))
  when(VecInit(io.readers.zip(nodeClients).collect { case (r, true) => r.req.fire }).asUInt.orR) { nodeReads := nodeReads + 1.U }
  io.stats.nodeStoreHits := 0.U
  io.stats.nodeStoreMisses := nodeReads
}
