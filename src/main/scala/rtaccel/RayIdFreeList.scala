package rtaccel

import chisel3._
import chisel3.util._
import rtaccel.leaf.GroupedRead

/** A pool of ray IDs `0 until numIds`, handed out on `alloc` and returned on
  * `free`, both ready/valid.
  *
  * IDs never issued yet come from a counter, so the pool is full straight out
  * of reset with no initialisation phase; returned IDs go through a FIFO of
  * depth `numIds`, which can therefore never overflow.
  *
  * An `inUse` bit per ID guards the invariant "no ray is lost or duplicated":
  * freeing an ID that is not allocated is dropped (so the ID cannot be handed
  * out twice) and raises the sticky `doubleFree` flag for the testbench and the
  * error counters.
  *
  * With `lateCheck` (the core's free list), a free's in-use bit is read in two
  * stages ([[rtaccel.leaf.GroupedRead]]) and the free takes effect a cycle later:
  * its bit is cleared, it is counted and it enters the FIFO from the read's
  * registers. In one stage the 1-of-numIds read ran into the FIFO's enqueue, the
  * error flag and the count (4 LUT and 3 MUXF, 4.94 ns, docs/fmax.md). The core
  * counts a ray whose hit has just left as held for that cycle.
  */
class RayIdFreeList(numIds: Int, lateCheck: Boolean = false) extends Module {
  require(numIds >= 2, s"RayIdFreeList: numIds must be >= 2, got $numIds")
  private val idBits = log2Ceil(numIds)

  val io = IO(new Bundle {
    val alloc = Decoupled(UInt(idBits.W))
    val free = Flipped(Decoupled(UInt(idBits.W)))

    /** Number of IDs currently allocated. */
    val inFlight = Output(UInt(log2Ceil(numIds + 1).W))

    /** Sticky: some `free` named an ID that was not allocated. */
    val doubleFree = Output(Bool())
  })
  override def desiredName = s"RayIdFreeList_n$numIds"

  // IDs below freshReg have been issued at least once.
  private val freshReg = RegInit(0.U(log2Ceil(numIds + 1).W))
  private val returned = Module(new Queue(UInt(idBits.W), numIds))
  // One bit per ID, a UInt rather than a Vec of Bools: the same flip-flops,
  // updated by two one-hot masks instead of one write port per bit (cheaper
  // for the C++ model to evaluate every cycle).
  private val inUseReg = RegInit(0.U(numIds.W))
  private val doubleFreeReg = RegInit(false.B)

  // freshReg =/= numIds, kept beside freshReg: the allocation's valid, its ID mux and the in-use update read a
  // register, not a compare of one (docs/fmax.md).
  private val haveFreshReg = RegInit(true.B)
  // The returned ID handed out next waits in a register (`headReg`), loaded from the FIFO or, when the FIFO is
  // empty, straight from the freed ID's register: the allocation's ID, its one-hot and the in-use update start
  // from registers, not from the FIFO's distributed-RAM read (docs/fmax.md). Loading the head from the freed ID
  // when the FIFO is empty keeps the time from a free to its ID's reuse at two cycles, and the FIFO's order.
  private val headValidReg = RegInit(false.B)
  private val headReg = Reg(UInt(idBits.W))
  // The FIFO's count (`queuedReg`) and whether it is empty (`queuedIs0Reg`): registers beside its pointers, kept
  // from its own enqueues and dequeues (StepCount), so that neither its pointer compare nor a subtraction of its
  // pointers lies on the handshake's path (docs/fmax.md).
  private val queued = new StepCount("queued", log2Ceil(numIds + 1), Seq(0))
  private val returnedAny = !queued.is(0)
  io.alloc.valid := haveFreshReg || headValidReg
  io.alloc.bits := Mux(haveFreshReg, freshReg(idBits - 1, 0), headReg)
  // The head is free for the next ID when empty or handed out now (fresh IDs go first).
  private val headFree = !headValidReg || (io.alloc.ready && !haveFreshReg)

  private val allocFire = io.alloc.fire

  /** A legal free (in the cycle it takes effect: its bit cleared, counted) and its ID. */
  private val (legalFree, legalId) = if (!lateCheck) {
    // The 1-of-numIds in-use read behind `freeLegal` ends in the freed-ID register below, not in the FIFO's write
    // enables (docs/fmax.md).
    io.free.ready := true.B
    val freeLegal = inUseReg(io.free.bits)
    val freeFire = io.free.valid && freeLegal
    // Were the same ID freed and re-allocated in one cycle, the allocation would
    // win (its mask is applied last); it cannot be, because a freed ID reaches
    // the head two cycles after its free. Any free clears its bit, legal or not: an
    // illegal free names a clear bit, so the clear changes nothing, and the bits'
    // update does not wait on the 1-of-numIds read of `freeLegal` (docs/fmax.md).
    val freeMask = Mux(io.free.valid, UIntToOH(io.free.bits, numIds), 0.U)
    val allocMask = Mux(allocFire, UIntToOH(io.alloc.bits, numIds), 0.U)
    inUseReg := (inUseReg & ~freeMask) | allocMask
    when(io.free.valid && !freeLegal) { doubleFreeReg := true.B }
    (freeFire, io.free.bits)
  } else {
    // The free's bit as it stood in its cycle, from the groups' registers; the free itself, registered. A free of
    // the ID freed the cycle before reads its bit before that free clears it, so it is illegal by the compare.
    io.free.ready := true.B
    val freeValidReg = RegNext(io.free.valid, false.B)
    val freeIdReg = RegNext(io.free.bits)
    val againReg = RegNext(io.free.valid && freeValidReg && io.free.bits === freeIdReg, false.B)
    val wasInUse = GroupedRead(inUseReg.asBools.map(_.asUInt), io.free.bits).asBool
    val freeFire = freeValidReg && wasInUse && !againReg
    // A freed ID reaches the head three cycles after its free at the earliest, so no allocation meets its clear.
    // Only a legal free clears its bit: an illegal one's ID may have been handed out since its read.
    val freeMask = Mux(freeFire, UIntToOH(freeIdReg, numIds), 0.U)
    val allocMask = Mux(allocFire, UIntToOH(io.alloc.bits, numIds), 0.U)
    inUseReg := (inUseReg & ~freeMask) | allocMask
    when(freeValidReg && !freeFire) { doubleFreeReg := true.B }
    (freeFire, freeIdReg)
  }

  // A legal free enters the FIFO (or the head) a cycle later, from registers. The FIFO, the head and that
  // register hold the IDs freed and not yet re-allocated, at most numIds - inFlight, so the FIFO always has room
  // (`no_overflow_returned`).
  private val freedValidReg = RegNext(legalFree, false.B)
  private val freedReg = RegEnable(legalId, legalFree)
  private val toHead = headFree && !returnedAny
  returned.io.enq.valid := freedValidReg && !toHead
  returned.io.enq.bits := freedReg
  returned.io.deq.ready := headFree && returnedAny
  when(headFree) {
    headValidReg := returnedAny || freedValidReg
    headReg := Mux(returnedAny, returned.io.deq.bits, freedReg)
  }
  private val enqFire = freedValidReg && !toHead
  private val deqFire = headFree && returnedAny
  queued.step(enqFire, deqFire)
  when(allocFire && haveFreshReg) {
    freshReg := freshReg + 1.U
    haveFreshReg := freshReg =/= (numIds - 1).U
  }
  // Counted from registered handshakes (HeldCount): the count's add was the unit's longest path, behind the
  // allocation's ready and the 1-of-numIds in-use read of a free (docs/fmax.md). It reads exactly.
  private val inFlight = HeldCount(Seq(allocFire), Seq(legalFree), log2Ceil(numIds + 1))

  // Checked in every simulation and proved by `make formal` (docs/formal.md);
  // they hold whatever `free` is driven with, since illegal frees are dropped.
  assert(!(allocFire && inUseReg(io.alloc.bits)), "id_allocated_once: an ID in flight was handed out again")
  assert(inFlight === PopCount(inUseReg), "id_count: the in-flight count disagrees with the IDs in use")
  assert(haveFreshReg === (freshReg =/= numIds.U), "id_fresh: the fresh flag disagrees with the fresh counter")
  assert(!returned.io.enq.valid || returned.io.enq.ready, "no_overflow_returned: a freed ID found the FIFO full")
  assert(returnedAny === returned.io.deq.valid, "id_returned: the FIFO's flag disagrees with the FIFO")
  assert(queued.countReg === returned.io.count, "id_queued: the FIFO's count disagrees with the FIFO")

  io.inFlight := inFlight
  io.doubleFree := doubleFreeReg
}
