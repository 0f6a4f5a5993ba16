package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.StepCount

/** A first-in first-out queue of `entries` in block RAM whose every decision starts at a register: the memory is
  * read synchronously at a pointer register, its data lands in a three-entry output buffer of registers whose head
  * is `deq` (its `valid` and `bits` are registers), and a read is started only when the buffer has room for it by
  * its registered occupancy. Held: up to `entries` in the memory and three in the buffer or on their way to it.
  *
  * chisel3.util's `Queue` reads its memory asynchronously; as block RAM, Yosys (like Vivado) reads it at the
  * pointer's next value, so the reader's handshake runs through the empty compare and the pointer's increment
  * into the RAM's address and its read-during-write compare (5.9 to 6.9 ns in the core, docs/fmax.md). Here the
  * handshake ends in the buffer's registers, and the memory side waits on registers alone.
  *
  * An entry written in one cycle is read no earlier than the next (the stored count that allows its read is
  * loaded by the write), so no read meets a write to the same entry. Throughput: one entry in and one out per
  * cycle; an entry reaches `deq` two cycles after it was written at the earliest.
  */
class RamQueue[T <: Data](gen: T, val entries: Int) extends Module {
  // One entry would pass one every other cycle (the full flag is a register): use HeadQueue.
  require(entries >= 2, s"RamQueue: entries = $entries, at least 2")
  val io = IO(new Bundle {
    val enq = Flipped(Decoupled(gen))
    val deq = Decoupled(gen)

    /** Entries held: in the memory, on their way out of it, and in the output buffer. */
    val count = Output(UInt(log2Ceil(entries + 4).W))
  })
  override def desiredName = s"RamQueue_${entries}"

  private val ptrBits = log2Ceil(entries).max(1)
  private val mem = SyncReadMem(entries, gen)
  private val wrPtrReg = RegInit(0.U(ptrBits.W))
  private val rdPtrReg = RegInit(0.U(ptrBits.W))
  // Written, not yet read; flagged full and empty beside the count, so the writer's valid, which comes late,
  // meets one select on its way to them (StepCount).
  private val stored = new StepCount("stored", log2Ceil(entries + 1), Seq(0, entries))
  private val full = stored.is(entries)
  private val have = !stored.is(0)
  private def bump(p: UInt): UInt = if (isPow2(entries)) p + 1.U else Mux(p === (entries - 1).U, 0.U, p + 1.U)

  // ---- Output buffer: three registers, the head first; an entry moves toward the head as the one ahead leaves ----
  private val slots = 3
  private val validRegs = RegInit(VecInit(Seq.fill(slots)(false.B)))
  private val dataRegs = Reg(Vec(slots, gen))
  private val inFlightReg = RegInit(false.B) // a read started last cycle: its data is at the memory's output now
  // Started only when the buffer is sure to have room when its data lands: at most two entries in the buffer and
  // on the way (registers only; one may leave meanwhile, which only leaves more room).
  private val occupiedReg = RegInit(0.U(2.W)) // buffer entries + the read on its way, as of this cycle, capped at 3
  private val start = have && occupiedReg < slots.U

  io.enq.ready := !full
  private val write = io.enq.fire
  when(write) {
    mem.write(wrPtrReg, io.enq.bits)
    wrPtrReg := bump(wrPtrReg)
  }
  private val readData = mem.read(rdPtrReg, start)
  when(start) { rdPtrReg := bump(rdPtrReg) }
  inFlightReg := start

  stored.step(write, start)

  io.deq.valid := validRegs(0)
  io.deq.bits := dataRegs(0)
  private val leave = io.deq.fire
  private val arrive = inFlightReg
  // Slot k after this cycle: the entry in slot k (or k+1 if the head left), else the arriving entry if it is the
  // first free one.
  for (k <- 0 until slots) {
    val stayValid = Mux(leave, if (k + 1 < slots) validRegs(k + 1) else false.B, validRegs(k))
    val stayData = if (k + 1 < slots) Mux(leave, dataRegs(k + 1), dataRegs(k)) else dataRegs(k)
    val firstFree = if (k == 0) true.B else Mux(leave, validRegs(k), validRegs(k - 1))
    val takes = arrive && !stayValid && firstFree
    validRegs(k) := stayValid || takes
    dataRegs(k) := Mux(takes, readData, stayData)
  }
  private val buffered = PopCount(validRegs)
  occupiedReg := buffered - leave.asUInt + arrive.asUInt + start.asUInt
  assert(!arrive || buffered - leave.asUInt < slots.U, "ram_queue_room: a read's data found the output buffer full")

  // Counted as entries pass, by the same select (a register: the units add their queues' counts).
  private val held = new StepCount("count", log2Ceil(entries + 4))
  held.step(write, leave)
  assert(
    held.countReg === stored.countReg +& inFlightReg.asUInt +& buffered,
    "ram_queue_count: the count differs from its parts"
  )
  assert(stored.flagsAgree, "ram_queue_flags: the stored count's full or empty flag disagrees with it")
  io.count := held.countReg
}

object RamQueue {

  /** The entries a RamQueue of `entries` holds before it refuses one: the memory's and the output buffer's three
    * (a read is started only for room in the buffer, so the one on its way is one of those three).
    */
  def capacity(entries: Int): Int = entries + 3
}
