package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4, Axi4Addr, Axi4Params, Axi4R}

/** The read half of the formal AXI4 slave (docs/formal.md, "System level"):
  * AR refused at most `stall` cycles in a row and while it holds `bursts`
  * bursts; beats of one ID in order, bursts of different IDs in any order
  * and interleaved; a burst older than `readLatency` cycles takes the R
  * channel (`axi_read_deadline`: an overdue one each cycle, which always
  * exists: the head of an overdue burst's ID is older, so overdue too); every
  * response OKAY. The parent gives each beat's data (`data`, from `beatAddr`)
  * and sees the beat's burst (`burstAddr`, `burstLen`). The master must take
  * every beat (`axi_r_taken`).
  */
class FormalAxiReadSlave(p: Axi4Params, readLatency: Int, stall: Int, bursts: Int) extends Module {
  require(isPow2(bursts), "FormalAxiReadSlave: bursts must be a power of two")
  val io = IO(new Bundle {
    val ar = Flipped(Decoupled(new Axi4Addr(p)))
    val r = Decoupled(new Axi4R(p))
    val data = Input(UInt(p.dataBits.W))
    val beatAddr = Output(UInt(p.addrBits.W))
    val burstAddr = Output(UInt(p.addrBits.W))
    val burstLen = Output(UInt(8.W))
  })
  private val K = bursts
  private val L = readLatency
  private val bValidRegs = RegInit(VecInit(Seq.fill(K)(false.B)))
  private val bIdRegs = Reg(Vec(K, UInt(p.idBits.W)))
  private val bAddrRegs = Reg(Vec(K, UInt(p.addrBits.W)))
  private val bLenRegs = Reg(Vec(K, UInt(8.W)))
  private val bCntRegs = Reg(Vec(K, UInt(8.W)))
  private val bAgeRegs = Reg(Vec(K, UInt(7.W)))
  private val full = bValidRegs.asUInt.andR
  io.ar.ready := !full && !FormalAxiReadSlave.stalled(io.ar.valid, io.ar.ready, stall)
  private val slot = PriorityEncoder(bValidRegs.map(!_))
  for (e <- 0 until K) when(bValidRegs(e) && bAgeRegs(e) =/= 127.U) { bAgeRegs(e) := bAgeRegs(e) + 1.U }
  when(io.ar.fire) {
    bValidRegs(slot) := true.B; bIdRegs(slot) := io.ar.bits.id; bAddrRegs(slot) := io.ar.bits.addr
    bLenRegs(slot) := io.ar.bits.len; bCntRegs(slot) := 0.U; bAgeRegs(slot) := 0.U
  }
  // The head of its ID: no older burst of the same ID waits (one AR a cycle, so ages differ).
  private val head = VecInit((0 until K).map(e =>
    bValidRegs(e) && (0 until K).filter(_ != e).map(f =>
      !(bValidRegs(f) && bIdRegs(f) === bIdRegs(e) && bAgeRegs(f) > bAgeRegs(e))
    ).foldLeft(true.B)(_ && _)
  ))
  private val sel = FormalAnySeq(UInt(log2Ceil(K).max(1).W))
  private val rValid = FormalAnySeq(Bool()) && head(sel)
  private val overdue = VecInit((0 until K).map(e => bValidRegs(e) && bAgeRegs(e) >= L.U))
  assume(!overdue.asUInt.orR || (rValid && overdue(sel)), "axi_read_deadline: an overdue burst takes the R channel")
  private val last = bCntRegs(sel) === bLenRegs(sel)
  io.beatAddr := bAddrRegs(sel) + (bCntRegs(sel) << log2Ceil(p.beatBytes))
  io.burstAddr := bAddrRegs(sel)
  io.burstLen := bLenRegs(sel)
  io.r.valid := rValid
  io.r.bits.id := bIdRegs(sel)
  io.r.bits.last := last
  io.r.bits.resp := Axi4.RespOkay.U
  io.r.bits.data := io.data
  assert(!io.r.valid || io.r.ready, "axi_r_taken: the master refused an R beat")
  when(io.r.fire) {
    bCntRegs(sel) := bCntRegs(sel) + 1.U
    when(last) { bValidRegs(sel) := false.B }
  }
}

object FormalAxiReadSlave {

  /** A refusal the model checker may choose, unless `stall` refusals in a row came before. */
  def stalled(valid: Bool, ready: Bool, stall: Int): Bool = {
    val stallReg = RegInit(0.U(log2Ceil(stall + 1).max(1).W))
    when(valid && !ready) { stallReg := stallReg + 1.U }.otherwise { stallReg := 0.U }
    if (stall == 0) false.B else FormalAnySeq(Bool()) && stallReg =/= stall.U
  }
}
