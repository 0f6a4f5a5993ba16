package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4, Axi4Addr, Axi4B, Axi4Params, Axi4W}

/** Writes 32-byte records as single-beat AXI4 bursts: the beat holds the
  * record in its half (address bit 5) and the strobes enable those 32 bytes
  * only. AW and W leave from their own two-entry queues (a record is taken
  * only when both have room), so each channel's payload is stable while it
  * waits for ready and neither channel waits for the other. All writes use
  * ID 0 and bready is always high; `writesDone` counts B responses, `error`
  * is sticky on a non-OKAY bresp. Writes outstanding are not bounded here:
  * the slave's awready bounds them.
  */
class WriteEngine(p: Axi4Params) extends Module {
  private val B = p.beatBytes
  private val R = WriteRecord.Bytes
  val io = IO(new Bundle {
    val write = Flipped(Decoupled(new Bundle {
      val addr = UInt(p.addrBits.W)
      val data = UInt((8 * R).W)
    }))
    val aw = Decoupled(new Axi4Addr(p))
    val w = Decoupled(new Axi4W(p))
    val b = Flipped(Decoupled(new Axi4B(p)))
    val writesDone = Output(UInt(32.W))
    val error = Output(Bool())
  })
  private val awQ = Module(new Queue(new Axi4Addr(p), 2))
  private val wQ = Module(new Queue(new Axi4W(p), 2))
  io.write.ready := awQ.io.enq.ready && wQ.io.enq.ready
  awQ.io.enq.valid := io.write.valid && wQ.io.enq.ready
  wQ.io.enq.valid := io.write.valid && awQ.io.enq.ready
  private val beatAddr = Cat(io.write.bits.addr(p.addrBits - 1, log2Ceil(B)), 0.U(log2Ceil(B).W))
  awQ.io.enq.bits := Axi4Addr.incr(p, 0.U, beatAddr, 1.U)
  // The record's place in the beat: address bits log2(B)-1 .. 5.
  private val half = io.write.bits.addr(log2Ceil(B) - 1, log2Ceil(R))
  wQ.io.enq.bits.data := Fill(B / R, io.write.bits.data)
  wQ.io.enq.bits.strb := (((BigInt(1) << R) - 1).U((B).W) << (half << log2Ceil(R)))(B - 1, 0)
  wQ.io.enq.bits.last := true.B
  io.aw <> awQ.io.deq
  io.w <> wQ.io.deq

  private val doneReg = RegInit(0.U(32.W))
  private val errorReg = RegInit(false.B)
  io.b.ready := true.B
  when(io.b.fire) {
    doneReg := doneReg + 1.U
    when(io.b.bits.resp =/= Axi4.RespOkay.U) { errorReg := true.B }
  }
  io.writesDone := doneReg
  io.error := errorReg
}
