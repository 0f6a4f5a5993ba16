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
  * The pair buffer: `SystemConfig.pairSlots` slots, slot = p mod slots. A
  * hit whose partner waits in its slot leaves with it as one line; a hit whose
  * partner is not in the batch (the odd last ray) leaves alone; a hit whose
  * slot is empty waits there for its partner; a hit whose slot holds another
  * pair leaves alone (the buffer never overflows: a hit is stored only in an
  * empty slot). Once every hit of the batch has been taken, a scan visits the
  * slots one a cycle, and what still waits there (a partner that had left
  * alone) leaves alone as the scan reaches it, so the batch's last record is
  * written at most `pairSlots` + 3 cycles after its last hit (and the hit
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
  // A register slice after the arbiter (two entries: a hit a cycle, its ready a register): the batch's compares
  // and the pair buffer's slot read start from a register, not from the cores' valids through the arbiter's
  // choice. Its head is a register too (HeadQueue, cycle for cycle a two-entry Queue): from a memory-held
  // Queue's distributed-RAM read, the held bits' multiplexer into `s2HeldRawReg` was 5.78 ns, and the `numbers`
  // read and the partner compare into its register 5.72 ns (docs/fmax.md).
  private val inQ = Module(new HeadQueue(new HitOut(sys.core)))
  inQ.io.enq <> arb.io.out
  private val baseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val countReg = RegInit(0.U(32.W))
  private val takenReg = RegInit(0.U(32.W))
  private val errReg = RegInit(VecInit(Seq.fill(ErrorFlags.width)(0.U(32.W))))
  private val brokenReg = RegInit(false.B)
  when(io.start) { baseReg := io.hitBase; countReg := io.rayCount; takenReg := 0.U; errReg.foreach(_ := 0.U) }

  // ---- The pair buffer ----
  // Two stages, each from registers, so that no slot read (a 256-deep LUTRAM or a 256-input mux of the held bits,
  // with 3 or 4 cores) lies on one path with the decision it feeds (that path was 9.8 ns at 256 slots): S1 reads
  // the head hit's slot into S2's registers; S2 decides from them. The flush has its own two stages (F1, F2).
  private val slots = sys.pairSlots
  private val slotBits = log2Ceil(slots)
  private val heldRegs = RegInit(VecInit(Seq.fill(slots)(false.B)))
  // A slot holds the record's six used words (its number the lowest), not its two zero words.
  private val records = Mem(slots, UInt(HitDma.UsedBits.W))
  // A held hit's line address, formed as it is stored, so that no adder follows the flush's slot read.
  private val lines = Mem(slots, UInt(sys.axiAddrBits.W))
  // A held hit's number again, for the partner compare: a memory of its own, read by the records' select (below).
  // Read by S1's slot alone, the input slice's head register would be its read address register, and Yosys makes
  // it a block RAM (2.46 ns clock-to-out: with the compare behind it, 6.00 ns); through the select it stays a
  // distributed-RAM read, and the compare is split into two registers.
  private val numbers = Mem(slots, UInt(32.W))
  private def slotOf(number: UInt): UInt = if (slots == 1) 0.U else (number >> 1)(slotBits - 1, 0)
  private def line(number: UInt): UInt = baseReg + ((number >> 1) << log2Ceil(WriteRecord.Bytes))

  // Every hit of the batch taken (of a stopped batch: every ray handed out): what still waits has no partner to come.
  // Registered, a cycle late (the flush waits a cycle more; no hit of the batch comes after it): the two 32-bit
  // compares in front of the pair buffer's slot select and the hit queue's enqueue were one path, 6.66 ns with
  // 3 cores (docs/fmax.md). Cleared by START, so a new batch never sees the last one's.
  private val allTaken = RegNext(!io.start && (takenReg === countReg || (io.stop && takenReg === io.issued)), false.B)

  // S2: a hit, its line, and its slot as S1 read it (held, and the held record), with S2's own action in the cycle
  // S1 read it beside them (`s2FwdReg`: S2 stored or took the hit of the same slot; `s2FwdStoreReg`: stored it),
  // which S2 applies: S1 registers its reads raw, so that the held bits' multiplexer (256 inputs at 3 or 4 cores)
  // ends in a register with no select behind it.
  private val s2ValidReg = RegInit(false.B)
  private val s2HitReg = Reg(new HitOut(sys.core))
  private val s2LineReg = Reg(UInt(sys.axiAddrBits.W))
  private val s2HeldRawReg = Reg(Bool())
  private val s2FwdReg = Reg(Bool())
  private val s2FwdStoreReg = Reg(Bool())
  private val s2HeldRecReg = Reg(UInt(HitDma.UsedBits.W))
  // Whether the slot's record (as read, and S2's own hit forwarded) is this hit's partner, compared in S1 (in S2 the
  // compare lay in front of the held bits' clear and the hit queue's fields, 4.94 ns at 128 slots). The compare
  // with the slot as read lands in one register per part of `HitDma.PartnerPart` bits, and S2 ANDs them beside its
  // other terms: behind the `numbers` read, one 25-bit equality was four LUTs into one register (5.72 ns with the
  // input slice's distributed-RAM read in front), and two halves a LUT and a MUXF7 each (5.18 ns, docs/fmax.md).
  private val partnerParts = HitDma.partnerParts(slotBits)
  private val s2PartnerReadRegs = Reg(Vec(partnerParts.size, Bool()))
  private val s2PartnerFwdReg = Reg(Bool())
  // The hit's two compares with RAY_COUNT, made in S1 (COUNT is set by START, before any hit of its batch): in S2
  // they would lie in front of the held bits' write decode (7.6 ns at 128 slots).
  private val s2InBatchReg = Reg(Bool())
  private val s2NoPartnerReg = Reg(Bool())
  // F1: the scan's slot (one a cycle) and its held bit, read from the held bits by `scanReg` alone.
  private val f1ValidReg = RegInit(false.B)
  private val f1SlotReg = Reg(UInt(slotBits.max(1).W))
  private val f1HeldReg = Reg(Bool())
  private val f1ClearedReg = Reg(Bool()) // F2 cleared F1's slot in the cycle F1 read it
  // F2: the flush's next waiting slot, from F1, with its record and line, held until its line leaves.
  private val fValidReg = RegInit(false.B)
  private val fSlotReg = Reg(UInt(slotBits.max(1).W))
  private val fRecReg = Reg(UInt(HitDma.UsedBits.W))
  private val fLineReg = Reg(UInt(sys.axiAddrBits.W))
  private val scanReg = RegInit(0.U(slotBits.max(1).W))

  // ---- S2: the decision ----
  private val h = s2HitReg
  private val rec = HitDma.used(h)
  private val slot = slotOf(h.number)
  private val inBatch = s2InBatchReg
  private val s2Held = Mux(s2FwdReg, s2FwdStoreReg, s2HeldRawReg)
  private val partnered = s2Held && Mux(s2FwdReg, s2PartnerFwdReg, s2PartnerReadRegs.asUInt.andR)
  private val store = !s2Held && !s2NoPartnerReg
  private val flushing = fValidReg

  // Hit queue: a record is enqueued only when it has room (valid/ready); a stored hit enqueues nothing.
  private val q = Module(new Queue(new WriteRecord(sys), sys.hitQueue))
  q.io.enq.valid := flushing || (s2ValidReg && inBatch && !store)
  // While flushing every hit of the batch has been taken: anything offered is out of the batch, held until after.
  private val s2Fire = s2ValidReg && !flushing && (q.io.enq.ready || store || !inBatch)

  /** A record alone: in both halves of the line, its own half's strobes only. */
  private def alone(number: UInt, r: UInt): (UInt, UInt) = (Fill(2, HitDma.pad(r)), UIntToOH(number(0), 2))
  private val (flushData, flushHalves) = alone(fRecReg(31, 0), fRecReg)
  private val (aloneData, aloneHalves) = alone(h.number, rec)
  // The even number's record in the low half.
  private val pairData =
    Mux(h.number(0), Cat(HitDma.pad(rec), HitDma.pad(s2HeldRecReg)), Cat(HitDma.pad(s2HeldRecReg), HitDma.pad(rec)))
  q.io.enq.bits.addr := Mux(flushing, fLineReg, s2LineReg)
  q.io.enq.bits.data := Mux(flushing, flushData, Mux(partnered, pairData, aloneData))
  q.io.enq.bits.halves := Mux(flushing, flushHalves, Mux(partnered, 3.U(2.W), aloneHalves))

  private val s2Stores = s2Fire && inBatch && store
  private val s2Clears = s2Fire && inBatch && partnered
  when(s2Fire) {
    when(!inBatch) { brokenReg := true.B }
    assert(inBatch, "hit_in_batch: a hit whose number is not in the batch")
    when(inBatch) { takenReg := takenReg + 1.U }
    for (k <- 0 until ErrorFlags.width) when(inBatch && h.errors(k)) { errReg(k) := errReg(k) + 1.U }
  }
  when(s2Clears) { heldRegs(slot) := false.B }
  when(s2Stores) {
    heldRegs(slot) := true.B
    records.write(slot, rec)
    numbers.write(slot, h.number)
    lines.write(slot, s2LineReg)
  }

  // ---- S1: the head hit's slot read into S2 ----
  // Moves when S2 is empty or leaves this cycle. S2's action this cycle is not yet in the slot S1 reads: forwarded
  // when it is the same slot (S2 stored there, or took the waiting hit out).
  private val in = inQ.io.deq
  private val s1Slot = slotOf(in.bits.number)
  in.ready := !s2ValidReg || s2Fire
  // One read of the record, line and number memories a cycle, shared: F1's slot once every hit of the batch is
  // taken (S1 then holds no hit of the batch, and S2 drops what it reads), else the head hit's. The held bits have
  // a read of their own for each (S1's here, the scan's below): one shared read's select in front of the held
  // bits' multiplexer was on the unit's longest path (docs/fmax.md).
  private val readSlot = Mux(allTaken, f1SlotReg, s1Slot)
  private val readHeld = heldRegs(s1Slot)
  private val readRec = records(readSlot)
  private val readLine = lines(readSlot)
  private val fwd = (s2Stores || s2Clears) && slot === s1Slot
  when(in.fire) {
    s2HitReg := in.bits
    s2LineReg := line(in.bits.number)
    s2InBatchReg := in.bits.number < countReg
    s2NoPartnerReg := (in.bits.number ^ 1.U) >= countReg
    s2HeldRawReg := readHeld
    s2FwdReg := fwd
    s2FwdStoreReg := s2Stores
    s2HeldRecReg := Mux(fwd && s2Stores, rec, readRec)
    // The held hit shares the slot's bits with this one's pair by construction: its partner differs in bit 0 only,
    // so the compare reads the bits above the slot's and bit 0. Both candidates (the slot as read, S2's own hit)
    // are compared side by side; S2 picks one by the forward. The slot as read is compared part by part.
    def partner(held: UInt, part: Seq[Int]): Bool =
      part.map(b => if (b == 0) held(0) =/= in.bits.number(0) else held(b) === in.bits.number(b)).reduce(_ && _)
    val number = numbers(readSlot)
    s2PartnerReadRegs := VecInit(partnerParts.map(partner(number, _)))
    s2PartnerFwdReg := partnerParts.map(partner(rec, _)).reduce(_ && _)
  }
  when(in.fire) { s2ValidReg := true.B }.elsewhen(s2Fire) { s2ValidReg := false.B }

  // ---- The flush: F1 scans a slot a cycle, F2 takes its record and line, F2's line leaves ----
  // The scan, from a register, so that no search for the first waiting slot (a 256-input tree) lies between the
  // pair buffer and its own clear; its held bit is read into F1 and taken by F2 a cycle later, so the held bits'
  // multiplexer ends in a register and F2's handshake does not follow it (in one cycle, 6.37 ns at 256 slots).
  // No hit of the batch comes while all are taken, so only the flush clears a slot then, and only in a cycle in
  // which F2's line leaves, which is also the only cycle in which a full F1 moves on: F2's clear in that cycle is
  // forwarded to F1's read and to F2's load (the same slot with one or two slots), so neither keeps a stale bit.
  private val fFire = flushing && q.io.enq.fire
  when(fFire) { heldRegs(fSlotReg) := false.B }
  private val fRoom = !fValidReg || fFire
  private val f1Room = !f1ValidReg || fRoom
  when(allTaken && f1Room) {
    f1ValidReg := true.B
    f1SlotReg := scanReg
    f1HeldReg := heldRegs(scanReg)
    f1ClearedReg := fFire && fSlotReg === scanReg
  }.elsewhen(!allTaken) { f1ValidReg := false.B }
  if (slots > 1) when(allTaken && f1Room) { scanReg := scanReg + 1.U }
  when(allTaken && f1ValidReg && fRoom) {
    fValidReg := f1HeldReg && !f1ClearedReg && !(fFire && fSlotReg === f1SlotReg)
    fSlotReg := f1SlotReg
    fRecReg := readRec
    fLineReg := readLine
  }.elsewhen(fFire) { fValidReg := false.B }
  io.write <> q.io.deq
  io.errCount := errReg
  io.broken := brokenReg
}

object HitDma {

  /** The 32-byte record, little-endian: number, status (bit 0 hit, bits 8.. errors), t, u, v, prim, 0, 0. Its six
    * used words, what the pair buffer holds; [[pad]] adds the two zero words. */
  def used(h: HitOut): UInt = {
    val status = Cat(h.errors, 0.U(7.W), h.hit)
    Cat(h.prim.pad(32), h.v, h.u, h.t, status.pad(32), h.number)
  }
  val UsedBits = 6 * 32

  /** The used words, then the two zero words: the whole record. */
  def pad(used: UInt): UInt = Cat(0.U((8 * SystemConfig.HitBytes - UsedBits).W), used)
  val StatusErrorShift = 8

  /** Entries of the register slice after the cores' arbiter (a HeadQueue): two take a hit a cycle with a
    * registered ready. */
  val InSlice = 2

  /** Bits of a hit's number per register of the partner compare: three. At 128 slots a part is the select of the
    * distributed RAM's two halves and two LUTs behind the read (4.89 ns from the read's slot select); two
    * halves of the compare took a MUXF7 more (5.18 ns); two bits a part leave the held bits' multiplexer the
    * unit's longest path at 4.94 ns in that netlist (docs/fmax.md). */
  val PartnerPart = 3

  /** The bits the partner compare reads (bit 0, which differs, and the bits above the slot's, which agree), in
    * parts of [[PartnerPart]]. */
  def partnerParts(slotBits: Int): Seq[Seq[Int]] = (0 +: (slotBits + 1 until 32)).grouped(PartnerPart).toSeq
}
