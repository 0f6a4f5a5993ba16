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

    /** Entries held (0 to 2), for the ray-conservation counts. */
    val count = Output(UInt(2.W))
  })
  private val headValidReg = RegInit(false.B)
  private val headReg = Reg(gen)
  private val spareValidReg = RegInit(false.B)
  private val spareReg = Reg(gen)
  io.enq.ready := !spareValidReg
  io.deq.valid := headValidReg
  io.deq.bits := headReg
  io.count := headValidReg.asUInt +& spareValidReg.asUInt
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

object HeadQueue {

  /** A HeadQueue after `in` (a memory-held `Queue`'s `deq`, typically): its reader then sees registers alone, and
    * the queue's read pointer waits on no more than the HeadQueue's registered `enq.ready`.
    */
  def apply[T <: Data](in: DecoupledIO[T]): HeadQueue[T] = {
    val h = Module(new HeadQueue(chiselTypeOf(in.bits)))
    h.io.enq <> in
    h
  }
}
