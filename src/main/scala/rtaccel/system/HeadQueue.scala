package rtaccel.system

import chisel3._
import chisel3.util._

/** A two-entry queue whose head is a register (`deq.bits` is read from no
  * memory and through no mux) and whose `enq.ready` is a register: a skid
  * buffer. One entry in and one out per cycle while the head drains.
  */
class HeadQueue[T <: Data](gen: T) extends Module {
  val io = IO(new Bundle {
    val enq = Flipped(Decoupled(gen))
    val deq = Decoupled(gen)
  })
  private val headValidReg = RegInit(false.B)
  private val headReg = Reg(gen)
  private val spareValidReg = RegInit(false.B)
  private val spareReg = Reg(gen)
  io.enq.ready := !spareValidReg
  io.deq.valid := headValidReg
  io.deq.bits := headReg
  // The head is free for the next entry when empty or leaving; the spare, when full, goes first (it came first).
  when(!headValidReg || io.deq.ready) {
    headValidReg := spareValidReg || io.enq.valid
    headReg := Mux(spareValidReg, spareReg, io.enq.bits)
    spareValidReg := false.B
  }.elsewhen(io.enq.valid && !spareValidReg) {
    spareValidReg := true.B
    spareReg := io.enq.bits
  }
}
