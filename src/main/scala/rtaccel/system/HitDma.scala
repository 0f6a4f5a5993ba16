package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.{ErrorFlags, HitOut}

/** Collects the cores' hits (round-robin) and writes each as the 32-byte hit
  * record at HIT_BASE + 32 * number (docs/reports/register-map.md), two
  * neighbours per 64-byte line where it can: hits 2p and 2p + 1 share the line
  * at HIT_BASE + 64 p (HIT_BASE is 64-byte aligned), and a line written as one
  * burst costs the DDR the same 64 bytes whether it carries one record or two
  * (docs/dram-traffic.md, `hits32`). Counts the batch's rays per error flag.
  *
  * The pair buffer: `SystemConfig.hitPairSlots` slots, slot = p mod slots. A
  * hit whose partner waits in its slot leaves with it as one line; a hit whose
  * partner is not in the batch (the odd last ray) leaves alone; a hit whose
  * slot is empty waits there for its partner; a hit whose slot holds another
  * pair leaves alone (the buffer never overflows: a hit is stored only in an
  * empty slot). Once every hit of the batch has been taken, a scan visits the
  * slots one a cycle, and what still waits there (a partner that had left
  * alone) leaves alone as the scan reaches it, so the batch's last record is
  * written at most `hitPairSlots` + 1 cycles after its last hit (and the hit
  * queue's refusals).
  * A stopped batch (ABORT, a fault: `stop`, `issued` rays handed out and no
  * more to come) flushes the same way once its `issued` hits are taken: a
  * hit waiting for a partner that was never handed out would otherwise wait
  * forever. Every hit of the batch is written exactly once, alone or paired.
  *
  * A hit whose number is not in the batch is not written and sets `broken`
  * (never expected: the ray DMA numbers rays 0..count-1).
  */
class HitDma(sys: SystemConfig) extends Module {
  val io = IO(new Bundle {
    val start = Input(Bool())
    val hitBase = Input(UInt(sys.axiAddrBits.W))
    val rayCount = Input(UInt(32.W))

    /** The batch stopped: `issued` of its rays were handed out, and no other will be. */
    val stop = Input(Bool())
    val issued = Input(UInt(32.W))
    val hits = Vec(sys.cores, Flipped(Decoupled(new HitOut(sys.core))))
    val write = Decoupled(new WriteRecord(sys))
    val errCount = Output(Vec(ErrorFlags.width, UInt(32.W)))
    val broken = Output(Bool())
  })
  private val arb = Module(new RRArbiter(new HitOut(sys.core), sys.cores))
  arb.io.in <> io.hits
  // A register slice after the arbiter (two entries: a hit a cycle, its ready from its own count): the batch's
  // compares and the pair buffer's slot read start from a register, not from the cores' valids through the
  // arbiter's choice.
  private val inQ = Module(new Queue(new HitOut(sys.core), HitDma.InSlice))
  inQ.io.enq <> arb.io.out
  private val in = inQ.io.deq
  private val baseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val countReg = RegInit(0.U(32.W))
  private val takenReg = RegInit(0.U(32.W))
  private val errReg = RegInit(VecInit(Seq.fill(ErrorFlags.width)(0.U(32.W))))
  private val brokenReg = RegInit(false.B)
  when(io.start) { baseReg := io.hitBase; countReg := io.rayCount; takenReg := 0.U; errReg.foreach(_ := 0.U) }

  // ---- The pair buffer ----
  private val slots = sys.hitPairSlots
  private val heldRegs = RegInit(VecInit(Seq.fill(slots)(false.B)))
  private val numbers = Mem(slots, UInt(32.W))
  private val records = Mem(slots, UInt((8 * SystemConfig.HitBytes).W))
  // A held hit's line address, formed as it is stored, so that no adder follows the flush's slot read.
  private val lines = Mem(slots, UInt(sys.axiAddrBits.W))
  private def slotOf(number: UInt): UInt = if (slots == 1) 0.U else (number >> 1)(log2Ceil(slots) - 1, 0)

  private val h = in.bits
  private val rec = HitDma.record(h)
  private val inBatch = h.number < countReg
  private val slot = slotOf(h.number)
  // Every hit of the batch taken (of a stopped batch: every ray handed out): what still waits has no partner to come.
  // Registered, a cycle late (the flush waits a cycle more; no hit of the batch comes after it): the two 32-bit
  // compares in front of the pair buffer's slot select and the hit queue's enqueue were one path, 6.66 ns with
  // 3 cores (docs/fmax.md). Cleared by START, so a new batch never sees the last one's.
  private val allTaken = RegNext(!io.start && (takenReg === countReg || (io.stop && takenReg === io.issued)), false.B)
  // The flush's scan: one slot a cycle, from a register, so that no search for the first waiting slot (a 64-input
  // tree) lies between the pair buffer and its own clear (that path would be the unit's longest, 6.69 ns).
  private val scanReg = RegInit(0.U(log2Ceil(slots).max(1).W))
  private val flushing = allTaken && heldRegs(scanReg)
  private val idx = Mux(flushing, scanReg, slot)
  private val heldNumber = numbers(idx)
  private val heldRecord = records(idx)
  private val heldLine = lines(idx)
  private val partnered = heldRegs(slot) && heldNumber === (h.number ^ 1.U)
  private val noPartner = (h.number ^ 1.U) >= countReg
  private val store = !heldRegs(slot) && !noPartner

  // Hit queue: a record is enqueued only when it has room (valid/ready); a stored hit enqueues nothing.
  private val q = Module(new Queue(new WriteRecord(sys), sys.hitQueue))
  q.io.enq.valid := flushing || (in.valid && inBatch && !store)
  // While flushing every hit of the batch has been taken: anything offered is out of the batch, held until after.
  in.ready := !flushing && (q.io.enq.ready || store || !inBatch)
  private def line(number: UInt): UInt = baseReg + ((number >> 1) << log2Ceil(WriteRecord.Bytes))

  /** A record alone: in both halves of the line, its own half's strobes only. */
  private def alone(number: UInt, r: UInt): (UInt, UInt) = (Fill(2, r), UIntToOH(number(0), 2))
  private val (flushData, flushHalves) = alone(heldNumber, heldRecord)
  private val (aloneData, aloneHalves) = alone(h.number, rec)
  // The even number's record in the low half.
  private val pairData = Mux(h.number(0), Cat(rec, heldRecord), Cat(heldRecord, rec))
  private val data = Mux(flushing, flushData, Mux(partnered, pairData, aloneData))
  private val halves = Mux(flushing, flushHalves, Mux(partnered, 3.U(2.W), aloneHalves))
  q.io.enq.bits.addr := Mux(flushing, heldLine, line(h.number))
  q.io.enq.bits.data := data
  q.io.enq.bits.halves := halves

  when(flushing && q.io.enq.fire) { heldRegs(scanReg) := false.B }
  // The scan moves on from an empty slot, or from a waiting one as it leaves.
  if (slots > 1) when(allTaken && (!heldRegs(scanReg) || q.io.enq.fire)) { scanReg := scanReg + 1.U }
  when(in.fire) {
    when(!inBatch) { brokenReg := true.B }
    assert(inBatch, "hit_in_batch: a hit whose number is not in the batch")
    when(inBatch) { takenReg := takenReg + 1.U }
    for (k <- 0 until ErrorFlags.width) when(inBatch && h.errors(k)) { errReg(k) := errReg(k) + 1.U }
    when(inBatch && partnered) { heldRegs(slot) := false.B }
    when(inBatch && store) {
      heldRegs(slot) := true.B
      numbers.write(slot, h.number)
      records.write(slot, rec)
      lines.write(slot, line(h.number))
    }
  }
  io.write <> q.io.deq
  io.errCount := errReg
  io.broken := brokenReg
}

object HitDma {

  /** The 32-byte record, little-endian: number, status (bit 0 hit, bits 8.. errors), t, u, v, prim, 0, 0. */
  def record(h: HitOut): UInt = {
    val status = Cat(h.errors, 0.U(7.W), h.hit)
    Cat(0.U(64.W), h.prim.pad(32), h.v, h.u, h.t, status.pad(32), h.number)
  }
  val StatusErrorShift = 8

  /** Entries of the register slice after the cores' arbiter: two take a hit a cycle with a ready from its count. */
  val InSlice = 2
}
