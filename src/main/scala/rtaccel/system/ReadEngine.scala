package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.{RayIdFreeList, RoundRobinArbiter}
import rtaccel.axi.{Axi4, Axi4Addr, Axi4Params, Axi4R, BurstMath, ByteRotate}

/** A record read on its way to DRAM: `client` picks the response queue. */
class ReadReq(addrBits: Int, clientBits: Int, tagBits: Int) extends Bundle {
  val addr = UInt(addrBits.W)
  val client = UInt(clientBits.W)
  val tag = UInt(tagBits.W)
}

/** A finished record for one client. */
class ReadResp(dataBits: Int, tagBits: Int) extends Bundle {
  val data = UInt(dataBits.W)
  val tag = UInt(tagBits.W)
}

/** Reads whole records of any byte size and alignment over AXI4.
  *
  * Each accepted request takes a *slot*, and the slot number is its AXI ID
  * (0 .. slots-1): one record per ID, so records come back in any order and
  * the beats of one record (one or more bursts split at 4 KB, same ID) come
  * in order. At most `slots` records are outstanding: that is the bound,
  * reached when the free-slot vector is empty (requests then wait).
  *
  * Reassembly: beat k of a record at byte offset o (address mod beatBytes) is
  * rotated right by o bytes; its first beatBytes - o bytes are record chunk k,
  * the rest chunk k - 1. Chunk c lives in bank c (one memory per chunk,
  * `slots` deep), so each beat writes at most one masked row into each of two
  * banks. When the last beat is written the slot joins its client's
  * completion queue, whose head waits in registers; a round-robin grant over
  * the heads takes it (registered), the next cycle reads the banks, the next
  * lands the record in the client's output queue (`ReadEngine.OutDepth`
  * entries) and frees the slot.
  *
  * Errors (sticky `error`): a non-OKAY rresp, an R beat whose ID names no
  * waiting record (dropped), or a wrong rlast.
  */
class ReadEngine(p: Axi4Params, recordBytes: Seq[Int], tagBits: Int, val slots: Int) extends Module {
  require(
    recordBytes.nonEmpty && recordBytes.forall(b => b >= 1 && b <= 4096),
    s"ReadEngine: record sizes must be 1..4096 bytes, got $recordBytes"
  )
  require(slots >= 2 && slots <= (1 << p.idBits), s"ReadEngine: $slots slots: 2 or more, in ${p.idBits} ID bits")
  private val n = recordBytes.size
  private val B = p.beatBytes
  private val beatBits = log2Ceil(B)
  private val slotBits = log2Ceil(slots).max(1)
  private val clientBits = log2Ceil(n).max(1)

  /** Chunks of the largest record: banks of the reassembly buffer. */
  private val chunks = recordBytes.map(b => (b + B - 1) / B).max

  /** Beats of the largest record at its worst alignment: ceil((o + b) / B) for o = B - 1. */
  private val maxBeats = recordBytes.map(b => (B + b - 2) / B + 1).max
  private val countBits = log2Ceil(maxBeats + 1)
  private val pageBits = log2Ceil(Axi4.BoundaryBytes) // 4 KB: no burst crosses a page

  val io = IO(new Bundle {
    val req = Flipped(Decoupled(new ReadReq(p.addrBits, clientBits, tagBits)))
    val ar = Decoupled(new Axi4Addr(p))

    /** R beats of this engine's IDs; always taken. */
    val r = Flipped(Valid(new Axi4R(p)))
    val resp = MixedVec(recordBytes.map(b => Decoupled(new ReadResp(8 * b, tagBits))))
    val error = Output(Bool())
    val idle = Output(Bool())
  })

  private class Meta extends Bundle {
    val client = UInt(clientBits.W)
    val tag = UInt(tagBits.W)

    /** The record's byte address within its 4 KB page: offset and beat position. */
    val page = UInt(pageBits.W)
    val beats = UInt(countBits.W)

    /** beats - 2 (mod 2^countBits): the count before which the next beat is the last. */
    val penult = UInt(countBits.W)
  }

  /** A slot drawn from the pool for a request to come: its index and one-hot. */
  private class DrawnSlot extends Bundle {
    val slot = UInt(slotBits.W)
    val oh = UInt(slots.W)
  }
  // Slot table: written when a slot is taken, read by R beats and the pick.
  private val meta = Mem(slots, new Meta)
  private val busyReg = RegInit(0.U(slots.W))
  private val doneReg = RegInit(0.U(slots.W)) // all beats in, not yet picked
  private val countRegs = RegInit(VecInit(Seq.fill(slots)(0.U(countBits.W))))
  // Whether a slot's next beat is its record's last (countRegs(s) === beats - 1), kept beside the count: an R
  // beat's completion reads one bit, not the count and the slot's beat count through a subtract and a compare
  // (that chain into the done bits was the fabric's longest path, docs/fmax.md).
  private val finalRegs = RegInit(VecInit(Seq.fill(slots)(false.B)))
  private val errorReg = RegInit(false.B)

  // ---- Issue: take a slot, then emit the record's bursts (split at 4 KB) ----
  private val pendValidReg = RegInit(false.B)
  private val pendAddrReg = Reg(UInt(p.addrBits.W)) // beat-aligned address of the next burst
  private val pendLeftReg = Reg(UInt(countBits.W))
  private val pendIdReg = Reg(UInt(slotBits.W))
  // The beats from pendAddrReg to its 4 KB boundary, kept beside it: loaded with each address (a full page
  // after a boundary), so the last-burst test, which the request's ready waits on, is one compare of two
  // registers, not a subtraction and a compare (through the ready and the client arbiter it was the
  // fabric's longest path, docs/fmax.md).
  private val toBoundaryReg = Reg(chiselTypeOf(BurstMath.beatsToBoundary(p, pendAddrReg)))
  private val burstBeats = Mux(pendLeftReg < toBoundaryReg, pendLeftReg, toBoundaryReg)
  private val lastBurst = pendLeftReg <= toBoundaryReg // = (burstBeats === pendLeftReg)
  assert(
    !pendValidReg || toBoundaryReg === BurstMath.beatsToBoundary(p, pendAddrReg),
    "read_to_boundary: the beats to the page boundary differ from the pending address's"
  )
  io.ar.valid := pendValidReg
  io.ar.bits := Axi4Addr.incr(p, pendIdReg, pendAddrReg, burstBeats)
  when(io.ar.fire) {
    // A burst that is not the record's last ends at the 4 KB boundary (burstBeats = toBoundary),
    // so the next one starts on the next page; after the last, the next request reloads the
    // address before it is used. The page number plus one is that address without the boundary
    // compare and the burst length in front of a 32-bit adder (Fmax, docs/fmax.md).
    // An address space of one page or less (the formal system's) has no next page: the address wraps to 0.
    pendAddrReg := (if (p.addrBits > pageBits) Cat(pendAddrReg(p.addrBits - 1, pageBits) + 1.U, 0.U(pageBits.W))
                    else 0.U)
    pendLeftReg := pendLeftReg - burstBeats
    toBoundaryReg := (Axi4.BoundaryBytes / B).U // a page start (0, wrapped, in a one-page space)
    when(lastBurst) { pendValidReg := false.B }
  }

  // The free slots are a pool (the one the cores' ray IDs use: never-used slots from a counter, freed ones
  // through a FIFO of `slots` entries, which cannot overflow), and the slot the next request takes is drawn ahead
  // into registers (index and one-hot): no search over `slots` bits lies anywhere, and only registers reach the
  // request handshake and the busy bits. A search for the first free bit, even a cycle ahead, was the fabric's
  // longest path, mapped as up to 10 LUT and MUXF cells (docs/fmax.md). The drawn slots wait in a HeadQueue (two
  // entries, its head and `enq.ready` registers), so the pool's draw does not wait on the request's handshake:
  // drawn as the request took the last one, the handshake ran through the pool's head into its FIFO's count,
  // 5.23 ns (docs/fmax.md). Slots are still taken in the pool's order, each a cycle after the pool offers it.
  private val pool = Module(new RayIdFreeList(slots))
  private val drawn = Module(new HeadQueue(new DrawnSlot))
  drawn.io.enq.valid := pool.io.alloc.valid
  drawn.io.enq.bits.slot := pool.io.alloc.bits
  drawn.io.enq.bits.oh := UIntToOH(pool.io.alloc.bits, slots)
  pool.io.alloc.ready := drawn.io.enq.ready
  private val newSlot = drawn.io.deq.bits.slot
  io.req.ready := drawn.io.deq.valid && (!pendValidReg || (io.ar.fire && lastBurst))
  drawn.io.deq.ready := io.req.fire
  // The beats a record covers, BurstMath.beatsCovering of its offset in a beat and its client's size b: with
  // b - 1 = q * B + r, q + 1, or q + 2 when the offset is B - r or more (it then crosses one more beat
  // boundary). A compare of the offset with a constant per client, then a select by the client: no adder
  // behind the client arbiter's choice, which through the size's select and the beat count's two adds into
  // pendLeftReg was the fabric's longest path (docs/fmax.md).
  private val reqOffset = io.req.bits.addr(beatBits - 1, 0)
  private val reqBeats = VecInit(recordBytes.map { b =>
    val (q, r) = ((b - 1) / B, (b - 1) % B)
    Mux(reqOffset >= (B - r).U, (q + 2).U(countBits.W), (q + 1).U(countBits.W))
  })(io.req.bits.client)
  assert(
    !io.req.valid || io.req.bits.client >= n.U ||
      reqBeats === BurstMath.beatsCovering(
        p,
        io.req.bits.addr,
        VecInit(recordBytes.map(_.U(13.W)))(io.req.bits.client)
      ),
    "read_beats: a record's beat count differs from the beats its bytes cover"
  )
  private val allocOH = Mux(io.req.fire, drawn.io.deq.bits.oh, 0.U)
  when(io.req.fire) {
    val m = Wire(new Meta)
    m.client := io.req.bits.client
    m.tag := io.req.bits.tag
    m.page := io.req.bits.addr(pageBits - 1, 0)
    m.beats := reqBeats
    m.penult := reqBeats - 2.U
    meta.write(newSlot, m)
    finalRegs(newSlot) := reqBeats === 1.U
    pendValidReg := true.B
    val addr = Cat(io.req.bits.addr(p.addrBits - 1, beatBits), 0.U(beatBits.W))
    pendAddrReg := addr
    toBoundaryReg := BurstMath.beatsToBoundary(p, addr)
    pendLeftReg := reqBeats
    pendIdReg := newSlot
  }

  // ---- R: read the beat's slot into registers, then count it, check it and write it to the banks ----
  // Two stages. The first reads the slot's state (waiting or not, beats counted, last-beat flag, table entry)
  // by the beat's ID into the `r1*` registers; the second updates that state, checks the beat and writes the
  // banks, all from those registers. The 1-of-`slots` read and the update were one path (through the busy and
  // done bits into the count and the flag, the fabric's longest: 5.83 ns, docs/fmax.md). A beat of the slot
  // the second stage is updating this cycle reads that update, not the stale registers (forwarded), so beats
  // of one ID may come back to back. The banks are written in the second stage, as a staged beat was before:
  // a record completes as early as it did.
  private val rId = io.r.bits.id
  private val rSlot = rId(slotBits - 1, 0)
  private val rMeta = meta(rSlot)
  private val r1ValidReg = RegNext(io.r.valid, false.B)
  private val r1SlotReg = RegEnable(rSlot, io.r.valid)
  private val r1KnownReg = Reg(Bool())
  private val r1CountReg = Reg(UInt(countBits.W))
  private val r1FinalReg = Reg(Bool())
  private val r1MetaReg = RegEnable(rMeta, io.r.valid)
  private val r1LastReg = RegEnable(io.r.bits.last, io.r.valid)
  private val r1OkayReg = RegEnable(io.r.bits.resp === 0.U, io.r.valid)
  private val r1DataReg = RegEnable(io.r.bits.data, io.r.valid)
  // A beat of a waiting record is kept even with an error, so the record
  // still completes (its client does not hang; `error` tells the host).
  private val r1Good = r1ValidReg && r1KnownReg
  private val nextCount = Mux(r1FinalReg, 0.U, r1CountReg + 1.U)
  private val nextFinal = !r1FinalReg && r1CountReg === r1MetaReg.penult
  when(r1Good) {
    countRegs(r1SlotReg) := nextCount
    finalRegs(r1SlotReg) := nextFinal
  }
  private val completeOH = Mux(r1Good && r1FinalReg, UIntToOH(r1SlotReg, slots), 0.U)
  assert(
    !r1Good || r1FinalReg === (r1CountReg === r1MetaReg.beats - 1.U),
    "read_final: a slot's last-beat flag is wrong"
  )
  // The slot's state as the second stage leaves it: its update forwarded to a beat of the same slot.
  private val sameSlot = r1Good && r1SlotReg === rSlot
  when(io.r.valid) {
    // A record's last beat ends its wait (the done bit is set as the stage ends): a further beat is unknown.
    r1KnownReg := rId < slots.U && Mux(sameSlot, !r1FinalReg, busyReg(rSlot) && !doneReg(rSlot))
    r1CountReg := Mux(sameSlot, nextCount, countRegs(rSlot))
    r1FinalReg := Mux(sameSlot, nextFinal, finalRegs(rSlot))
  }
  // The beat's checks, from the second stage's registers: it ends a burst where its record ends or where the next
  // beat would start a new 4 KB page, and its response is OKAY. The next beat starts a page when the record's
  // first beat in its page, plus the count, plus one is 0 modulo the beats of a page: when the count is the first
  // beat's complement (-x - 1 = ~x), one equality of registers. As that sum and a compare with 0 into the error
  // flag it was the fabric's longest path, 5.23 ns (docs/fmax.md).
  private val pageBeatBits = pageBits - beatBits
  private val chkEndsPage =
    r1CountReg.pad(pageBeatBits)(pageBeatBits - 1, 0) === ~r1MetaReg.page(pageBits - 1, beatBits)
  assert(
    !r1ValidReg || chkEndsPage ===
      ((r1MetaReg.page(pageBits - 1, beatBits) +& r1CountReg + 1.U)(pageBeatBits - 1, 0) === 0.U),
    "read_page_end: the beat's page-end test differs from its beat in the page"
  )
  private val chkLastOk = r1LastReg === (r1FinalReg || chkEndsPage)
  when(r1ValidReg && !(r1KnownReg && chkLastOk && r1OkayReg)) { errorReg := true.B }

  private val r1Off = r1MetaReg.page(beatBits - 1, 0)

  private val banks = Seq.fill(chunks)(SyncReadMem(slots, Vec(B, UInt(8.W))))
  private val rotated = ByteRotate.right(r1DataReg, r1Off).asTypeOf(Vec(B, UInt(8.W)))
  // Bytes j < B - o of the rotated beat belong to chunk k, the others to chunk k - 1. As o <= B - 1 - j: each
  // bit a compare of the offset with a constant (one LUT), not a subtraction then a compare in front of the
  // banks' byte enables (their longest path, 5.54 ns, docs/fmax.md).
  private val lowMask = VecInit((0 until B).map(j => r1Off <= (B - 1 - j).U))
  private val highMask = VecInit(lowMask.map(!_))
  for ((bank, c) <- banks.zipWithIndex) {
    val own = r1CountReg === c.U
    val next = r1CountReg === (c + 1).U
    when(r1Good && (own || next)) { bank.write(r1SlotReg, rotated, Mux(own, lowMask, highMask)) }
  }

  // Each slot enters one completion queue once per use, so `slots` entries never overflow.
  private val completions = Seq.fill(n)(Module(new Queue(UInt(slotBits.W), slots)))
  for ((q, c) <- completions.zipWithIndex) {
    q.io.enq.valid := r1Good && r1FinalReg && r1MetaReg.client === c.U
    q.io.enq.bits := r1SlotReg
    when(q.io.enq.valid && !q.io.enq.ready) { errorReg := true.B } // impossible (above); checked
    assert(
      !(q.io.enq.valid && !q.io.enq.ready),
      "no_overflow_read_completion: a finished record found its completion queue full"
    )
  }

  // ---- Pick a finished record (grant, select, then read), queue it for its client ----
  // Each completion queue drains into a two-entry HeadQueue, whose head and `enq.ready` are registers, so the
  // round-robin grant starts from registers (the head's valid, the client's credit) and the queue's pointers
  // do not wait on the grant. The grant lands in `selOHReg` (one-hot) and the granted head's slot in that
  // client's `takenSlotRegs`: no slot select follows the grant in its cycle. The select stage forms the slot
  // (an AND-OR of `takenSlotRegs` by `selOHReg`) and reads the banks and the slot's tag; the read stage frees
  // the slot; the record enters the output queue the cycle after. A binary choice and a slot select behind the
  // pick, through a queue's pointer compare, were the fabric's longest paths (docs/fmax.md).
  private val outQs = recordBytes.map(b => Module(new Queue(new ReadResp(8 * b, tagBits), ReadEngine.OutDepth)))
  private val heads = Seq.fill(n)(Module(new HeadQueue(UInt(slotBits.W))))
  private val selValidReg = RegInit(false.B)
  private val selOHReg = RegInit(0.U(n.W))
  private val takenSlotRegs = Reg(Vec(n, UInt(slotBits.W)))
  private val pickValidReg = RegInit(false.B)
  private val pickOHReg = RegInit(0.U(n.W))
  private val pickSlotReg = Reg(UInt(slotBits.W))
  private val pickTagReg = Reg(UInt(tagBits.W))
  private val arb = Module(new RoundRobinArbiter(UInt(1.W), n)) // grants only: the slot is taken beside it
  // Credit: queued + selected + being read < OutDepth, so every record granted
  // now has a place in its queue when it arrives two cycles later: the
  // queue only loses entries meanwhile, and both stages ahead of it count.
  // The sum is kept in a register per client (`heldReg`: +1 when the arbiter
  // grants the client, -1 when the client takes a record), so the arbiter's
  // request valids start from a 2-bit compare of a register, not from the
  // queue's count and the stages' adds (that chain through the arbiter into
  // the select registers was the fabric's longest path, docs/fmax.md).
  private val heldRegs = Seq.fill(n)(RegInit(0.U(log2Ceil(ReadEngine.OutDepth + 1).W)))
  for ((heldReg, c) <- heldRegs.zipWithIndex) {
    val inSel = selValidReg && selOHReg(c)
    val inRead = pickValidReg && pickOHReg(c)
    assert(
      heldReg === outQs(c).io.count +& inSel.asUInt +& inRead.asUInt,
      "read_out_credit: a client's credit count differs from its queued, selected and read records"
    )
    val credit = heldReg < ReadEngine.OutDepth.U
    heads(c).io.enq <> completions(c).io.deq
    arb.io.in(c).valid := heads(c).io.deq.valid && credit
    arb.io.in(c).bits := 0.U
    val take = arb.io.in(c).fire
    heads(c).io.deq.ready := take
    when(take) { takenSlotRegs(c) := heads(c).io.deq.bits }
    heldReg := heldReg + take.asUInt - outQs(c).io.deq.fire.asUInt
  }
  arb.io.out.ready := true.B
  selValidReg := arb.io.out.valid
  selOHReg := VecInit(arb.io.in.map(_.fire)).asUInt
  private val selSlot = Mux1H(selOHReg, takenSlotRegs)
  private val record = Cat(banks.reverse.map(b => b.read(selSlot, selValidReg).asUInt))
  pickValidReg := selValidReg
  when(selValidReg) {
    pickOHReg := selOHReg
    pickSlotReg := selSlot
    pickTagReg := meta(selSlot).tag
  }
  // The slot is free once its banks have been read: it is taken again at the
  // earliest next cycle, and its new record's beats come after a new AR.
  private val freeOH = Mux(pickValidReg, UIntToOH(pickSlotReg, slots), 0.U)
  pool.io.free.valid := pickValidReg
  pool.io.free.bits := pickSlotReg
  when(pool.io.doubleFree) { errorReg := true.B } // impossible (read_slot_freed_once); checked
  busyReg := (busyReg | allocOH) & ~freeOH
  // Each slot (AXI ID) holds one record per use: taken only when free, freed only when taken.
  assert((busyReg & allocOH) === 0.U, "read_slot_taken_once: a request took a slot that holds a record")
  assert(!pickValidReg || busyReg(pickSlotReg), "read_slot_freed_once: a slot was freed that holds no record")
  doneReg := (doneReg | completeOH) & ~freeOH

  for (c <- 0 until n) {
    val q = outQs(c).io
    q.enq.valid := pickValidReg && pickOHReg(c)
    q.enq.bits.data := record(8 * recordBytes(c) - 1, 0)
    q.enq.bits.tag := pickTagReg
    // Impossible by the credit above; checked all the same.
    when(q.enq.valid && !q.enq.ready) { errorReg := true.B }
    assert(!(q.enq.valid && !q.enq.ready), "no_overflow_read_out: a picked record found its client's output queue full")
    io.resp(c) <> q.deq
  }
  io.error := errorReg
  io.idle := busyReg === 0.U && !pendValidReg
}

object ReadEngine {

  /** Output queue per client: the select and read stages ahead of it + 1, so a client that always takes gets one record per cycle. */
  val OutDepth = 3
}
