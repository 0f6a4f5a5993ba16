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

    /** The same read, every bank's output ([[StackRead.value]] is `popVal`): a consumer that registers it first
      * combines the banks after its register, not after the block RAM's output. */
    val popRead = Output(new StackRead(cfg))

    /** Port B: pop slot `spB - 1` of ray `rayIdB`; the value the next cycle. */
    val rayIdB = Input(UInt(cfg.rayIdBits.W))
    val spB = Input(UInt(cfg.stackPtrBits.W))
    val popB = Input(Bool())
    val popValB = Output(new ChildRef(cfg))
    val popReadB = Output(new StackRead(cfg))
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
  // Bank b's row for the push that lands on it: the slot is sp + ((b - sp) mod B), so its row is sp's row, or the
  // next when sp's bank bits are above b. Both rows are registered with the push, so a bank's write address is
  // one select of registers by a compare of sp's low bits with a constant. Formed from the registered sp (an add
  // per push and a select of the slots), the address ran into the block RAM's read-during-write compare
  // (5.30 ns, docs/fmax.md).
  // (With one row the address is the ray ID; with a row count not a power of two, the slot's add stays.)
  private val rowsSplit = cfg.stackRows > 1 && isPow2(cfg.stackRows)
  private val pushRow: Int => UInt = if (!rowsSplit) (_ => 0.U)
  else {
    val rowBits = log2Ceil(cfg.stackRows)
    val row = (io.sp >> bankBits)(rowBits - 1, 0)
    val wRowReg = RegNext(row)
    val wNextRowReg = RegNext(row + 1.U)
    b => if (banks == 1) wRowReg else Mux(wSpReg(bankBits - 1, 0) > b.U, wNextRowReg, wRowReg)
  }
  for (((mem, memB), b) <- mems.zip(memsB).zipWithIndex) {
    val hits = (0 until pushes).map(p => p.U < wCountReg && landsOn(wSpReg, p, b))
    when(hits.reduce(_ || _)) {
      val addr =
        if (rowsSplit) Cat(wRayIdReg, pushRow(b))
        else rowAddr(Mux1H(hits, slots), wRayIdReg)
      assert(addr === rowAddr(Mux1H(hits, slots), wRayIdReg), "stack_push_row: a push's row is not its slot's")
      val value = Mux1H(hits, wValsReg)
      mem.write(addr, value)
      memB.write(addr, value)
    }
  }
  private def popPort(ms: Seq[SyncReadMem[ChildRef]], rayId: UInt, sp: UInt, pop: Bool): StackRead = {
    val slot = sp.pad(slotBits) - 1.U
    val r = Wire(new StackRead(cfg))
    // Each bank's output is kept only by the bank that holds the entry (its read enable, registered), so the
    // entry is the OR of the banks. The AND is one LUT after the block RAM, before any register a consumer puts
    // there: with none, Yosys takes that register for the RAM's own output stage, and the RAM's clock-to-out then
    // runs into everything after it (6.34 ns in Traversal, docs/fmax.md).
    r.banks := VecInit(ms.zipWithIndex.map { case (mem, b) =>
      val en = pop && landsOn(sp, -1, b)
      val data = mem.read(rowAddr(slot, rayId), en)
      if (banks == 1) data else Mux(RegEnable(en, false.B, pop), data, 0.U.asTypeOf(data))
    })
    r
  }
  io.popRead := popPort(mems, io.rayId, io.sp, io.pop)
  io.popReadB := popPort(memsB, io.rayIdB, io.spB, io.popB)
  io.popVal := io.popRead.value
  io.popValB := io.popReadB.value
}

/** A pop's read: each bank's output, all zero but the one bank that holds the popped entry. */
class StackRead(cfg: AccelConfig) extends Bundle {
  val banks = Vec(cfg.stackBanks, new ChildRef(cfg))

  /** The popped entry. */
  def value: ChildRef = banks.map(_.asUInt).reduce(_ | _).asTypeOf(new ChildRef(cfg))
}
