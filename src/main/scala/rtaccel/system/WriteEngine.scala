package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4, Axi4Addr, Axi4B, Axi4Params, Axi4W}

/** Writes 64-byte lines of 32-byte records (WriteRecord) as single-beat AXI4
  * bursts: the beat holds the line in its place (address bits above 6 within
  * the beat, at 1024 bits) and the strobes enable the records the line
  * carries only (one or both halves). AW and W leave from their own two-entry
  * queues (a line is taken only when both have room), so each channel's
  * payload is stable while it waits for ready and neither channel waits for
  * the other. All writes use ID 0, so B responses come in order; bready is
  * always high. `writesDone` counts the records of the writes whose B has
  * come (a line's one or two), read from a queue of the records per write in
  * flight: a line is taken only while that queue has room, so at most
  * `maxOutstanding` writes are in flight and the queue never overflows. A
  * write's records reach `writesDone` two cycles after its B (the add is
  * registered).
  * `error` is sticky on a non-OKAY bresp or a B for no write.
  */
class WriteEngine(p: Axi4Params, maxOutstanding: Int = WriteEngine.MaxOutstanding) extends Module {
  private val B = p.beatBytes
  private val L = WriteRecord.Bytes
  private val R = WriteRecord.RecordBytes
  require(B >= L, s"WriteEngine: a beat ($B bytes) must hold a $L-byte line")
  val io = IO(new Bundle {
    val write = Flipped(Decoupled(new Bundle {
      val addr = UInt(p.addrBits.W)
      val data = UInt((8 * L).W)
      val halves = UInt(WriteRecord.Records.W)
    }))
    val aw = Decoupled(new Axi4Addr(p))
    val w = Decoupled(new Axi4W(p))
    val b = Flipped(Decoupled(new Axi4B(p)))
    val writesDone = Output(UInt(32.W))
    val error = Output(Bool())
  })
  private val awQ = Module(new Queue(new Axi4Addr(p), 2))
  private val wQ = Module(new Queue(new Axi4W(p), 2))
  private val recordsQ = Module(new Queue(UInt(2.W), maxOutstanding))
  private val room = Seq(awQ.io.enq.ready, wQ.io.enq.ready, recordsQ.io.enq.ready)
  io.write.ready := room.reduce(_ && _)
  awQ.io.enq.valid := io.write.valid && wQ.io.enq.ready && recordsQ.io.enq.ready
  wQ.io.enq.valid := io.write.valid && awQ.io.enq.ready && recordsQ.io.enq.ready
  recordsQ.io.enq.valid := io.write.valid && awQ.io.enq.ready && wQ.io.enq.ready
  recordsQ.io.enq.bits := PopCount(io.write.bits.halves)
  private val beatAddr = Cat(io.write.bits.addr(p.addrBits - 1, log2Ceil(B)), 0.U(log2Ceil(B).W))
  awQ.io.enq.bits := Axi4Addr.incr(p, 0.U, beatAddr, 1.U)
  // The line's place in the beat: address bits log2(B)-1 .. 6 (none at 512 bits).
  private val place = if (B == L) 0.U else io.write.bits.addr(log2Ceil(B) - 1, log2Ceil(L))
  private val lineStrb = Cat((WriteRecord.Records - 1 to 0 by -1).map(h => Fill(R, io.write.bits.halves(h))))
  wQ.io.enq.bits.data := Fill(B / L, io.write.bits.data)
  wQ.io.enq.bits.strb := (lineStrb.pad(B) << (place << log2Ceil(L)))(B - 1, 0)
  wQ.io.enq.bits.last := true.B
  io.aw <> awQ.io.deq
  io.w <> wQ.io.deq

  private val doneReg = RegInit(0.U(32.W))
  private val errorReg = RegInit(false.B)
  io.b.ready := true.B
  recordsQ.io.deq.ready := io.b.valid
  // A B's records are added a cycle after it comes: the queue's empty test and the select in front of the
  // 32-bit add were the fabric's longest path (docs/fmax.md). writesDone counts them a cycle later for it.
  private val doneAddReg = RegNext(Mux(io.b.fire && recordsQ.io.deq.valid, recordsQ.io.deq.bits, 0.U), 0.U(2.W))
  doneReg := doneReg + doneAddReg
  when(io.b.fire) {
    when(io.b.bits.resp =/= Axi4.RespOkay.U || !recordsQ.io.deq.valid) { errorReg := true.B }
  }
  io.writesDone := doneReg
  io.error := errorReg
}

object WriteEngine {

  /** Writes in flight (AW taken, B not yet come) at most: a hit line every 2 cycles (4 cores at 0.54 rays/cycle,
    * docs/reports/performance.md) against B responses the DDR model gives within about 40 cycles keeps fewer
    * than 32 in flight, so the bound costs nothing measured. */
  val MaxOutstanding = 32
}
