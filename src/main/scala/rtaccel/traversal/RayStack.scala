package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig
import rtaccel.bvh.ChildRef

/** Every ray's traversal stack, in `cfg.stackBanks` on-chip memories.
  *
  * Entry `s` of ray `id` lives in bank `s mod B`, row `id * stackRows + s / B`:
  * stacks of different rays never overlap (the seed addressed them wrongly),
  * and a decision's pushes, which go to the consecutive slots `sp .. sp+n-1`
  * with `n <= B`, fall into distinct banks, so every bank takes at most one
  * write per cycle and stays a simple dual-port block RAM.
  *
  * Port A (TraversalControl's box-result lane) either pushes up to
  * `layout.maxPushes` entries or pops one (slot `sp - 1`); port B (its
  * leaf-return lane) only pops. A popped value appears the next cycle
  * (synchronous read); pushes are written the cycle after they are offered.
  * Each bank is kept twice, written together, so each port has a read port
  * of its own. The two ports always serve different rays, and a ray is never
  * in TraversalControl twice at once nor in two cycles in a row, so no access
  * meets a write to the same entry in flight (no read-after-write hazard).
  */
class RayStack(cfg: AccelConfig) extends Module {
  private val pushes = cfg.layout.maxPushes
  private val slotBits = log2Ceil(cfg.stackDepth + pushes + 1)
  val io = IO(new Bundle {
    val rayId = Input(UInt(cfg.rayIdBits.W))

    /** The ray's stack pointer: pushes fill slots sp, sp+1, ...; a pop reads sp - 1. */
    val sp = Input(UInt(cfg.stackPtrBits.W))

    /** Entries to push this cycle, `pushVals(0 until pushCount)`. */
    val pushCount = Input(UInt(log2Ceil(pushes + 1).W))
    val pushVals = Input(Vec(pushes, new ChildRef(cfg)))
    val pop = Input(Bool())

    /** The entry read by a pop in the previous cycle. */
    val popVal = Output(new ChildRef(cfg))

    /** Port B: pop slot `spB - 1` of ray `rayIdB`; the value the next cycle. */
    val rayIdB = Input(UInt(cfg.rayIdBits.W))
    val spB = Input(UInt(cfg.stackPtrBits.W))
    val popB = Input(Bool())
    val popValB = Output(new ChildRef(cfg))
  })
  override def desiredName = s"RayStack_n${cfg.numRayIds}_d${cfg.stackDepth}_b${cfg.stackBanks}"

  private val banks = cfg.stackBanks
  private val bankBits = log2Ceil(banks)
  private val mems = Seq.fill(banks)(SyncReadMem(cfg.numRayIds * cfg.stackRows, new ChildRef(cfg)))
  private val memsB = Seq.fill(banks)(SyncReadMem(cfg.numRayIds * cfg.stackRows, new ChildRef(cfg)))
  // With a power-of-two row count the row address is the ray ID beside the
  // slot's row bits, with no adder after the push slot's (the unit's longest
  // path, docs/fmax.md). Keeping only the row bits is exact: TraversalControl
  // pushes only slots below stackDepth (it sets StackOverflow instead), so a
  // written slot's row is below stackRows, and a pop reads sp - 1 < stackDepth.
  private def rowAddr(slot: UInt, rayId: UInt = io.rayId): UInt =
    if (cfg.stackRows == 1) rayId
    else if (isPow2(cfg.stackRows)) Cat(rayId, (slot >> bankBits)(log2Ceil(cfg.stackRows) - 1, 0))
    else rayId * cfg.stackRows.U + (slot >> bankBits)
  private def bankOf(slot: UInt): UInt = if (banks == 1) 0.U else slot(bankBits - 1, 0)

  // Push port p writes slot sp + p; bank b takes the port whose slot lands on it.
  // Slot sp + p lands on bank b exactly when sp's bank bits are (b - p) mod B: a compare of sp's low bits with
  // a constant, not of the sum's, so a bank's write enable is one function of those bits and pushCount, with no
  // adder's carry chain in front of it (that was the unit's longest path, docs/fmax.md).
  // The pushes are registered and written a cycle after their decision: the decision's logic and the memories'
  // write enables and data are not one path (docs/fmax.md). A ray is back in TraversalControl many cycles after
  // a decision (a node fetch and the box test, or a leaf), so no read of its stack meets a write still waiting.
  private val wRayIdReg = RegNext(io.rayId)
  private val wSpReg = RegNext(io.sp)
  private val wCountReg = RegNext(io.pushCount, 0.U)
  private val wValsReg = RegNext(io.pushVals)
  private val slots = (0 until pushes).map(p => wSpReg.pad(slotBits) + p.U)
  // The contract this relies on, checked in every simulation and in formal: no pop, on either port, reads a ray
  // whose pushes still wait in the write registers.
  assert(
    !(wCountReg =/= 0.U && ((io.pop && io.rayId === wRayIdReg) || (io.popB && io.rayIdB === wRayIdReg))),
    "stack_pop_after_push: a ray is popped the cycle after its push, before the push is written"
  )
  private def landsOn(sp: UInt, offset: Int, b: Int): Bool =
    if (banks == 1) true.B else sp(bankBits - 1, 0) === Math.floorMod(b - offset, banks).U
  for (((mem, memB), b) <- mems.zip(memsB).zipWithIndex) {
    val hits = (0 until pushes).map(p => p.U < wCountReg && landsOn(wSpReg, p, b))
    when(hits.reduce(_ || _)) {
      val (addr, value) = (rowAddr(Mux1H(hits, slots), wRayIdReg), Mux1H(hits, wValsReg))
      mem.write(addr, value)
      memB.write(addr, value)
    }
  }
  private def popPort(ms: Seq[SyncReadMem[ChildRef]], rayId: UInt, sp: UInt, pop: Bool): ChildRef = {
    val slot = sp.pad(slotBits) - 1.U
    val reads = ms.zipWithIndex.map { case (mem, b) => mem.read(rowAddr(slot, rayId), pop && landsOn(sp, -1, b)) }
    if (banks == 1) reads.head else VecInit(reads)(RegEnable(bankOf(slot), pop))
  }
  io.popVal := popPort(mems, io.rayId, io.sp, io.pop)
  io.popValB := popPort(memsB, io.rayIdB, io.spB, io.popB)
}
