package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ChildRef}

/** Every ray's traversal stack, in `cfg.stackBanks` on-chip memories.
  *
  * Entry `s` of ray `id` lives in bank `s mod B`, row `id * stackRows + s / B`:
  * stacks of different rays never overlap (the seed addressed them wrongly),
  * and a decision's pushes, which go to the consecutive slots `sp .. sp+n-1`
  * with `n <= B`, fall into distinct banks, so every bank takes at most one
  * write per cycle and stays a simple dual-port block RAM.
  *
  * One ray per cycle: it either pushes up to `layout.maxPushes` entries or
  * pops one (slot `sp - 1`), whose value appears the next cycle (synchronous
  * read). A ray is never in TraversalControl twice at once, so consecutive
  * accesses belong to different rays and there is no read-after-write hazard.
  */
class RayStack(cfg: AccelConfig) extends Module {
  private val pushes = cfg.layout.maxPushes
  private val slotBits = log2Ceil(cfg.stackDepth + pushes + 1)
  val io = IO(new Bundle {
    val rayId     = Input(UInt(cfg.rayIdBits.W))
    /** The ray's stack pointer: pushes fill slots sp, sp+1, ...; a pop reads sp - 1. */
    val sp        = Input(UInt(cfg.stackPtrBits.W))
    /** Entries to push this cycle, `pushVals(0 until pushCount)`. */
    val pushCount = Input(UInt(log2Ceil(pushes + 1).W))
    val pushVals  = Input(Vec(pushes, new ChildRef(cfg)))
    val pop       = Input(Bool())
    /** The entry read by a pop in the previous cycle. */
    val popVal    = Output(new ChildRef(cfg))
  })
  override def desiredName = s"RayStack_n${cfg.numRayIds}_d${cfg.stackDepth}_b${cfg.stackBanks}"

  private val banks = cfg.stackBanks
  private val bankBits = log2Ceil(banks)
  private val mems = Seq.fill(banks)(SyncReadMem(cfg.numRayIds * cfg.stackRows, new ChildRef(cfg)))
  private def rowAddr(slot: UInt): UInt = io.rayId * cfg.stackRows.U + (slot >> bankBits)
  private def bankOf(slot: UInt): UInt = if (banks == 1) 0.U else slot(bankBits - 1, 0)

  // Push port p writes slot sp + p; bank b takes the port whose slot lands on it.
  private val slots = (0 until pushes).map(p => io.sp.pad(slotBits) + p.U)
  for ((mem, b) <- mems.zipWithIndex) {
    val hits = slots.zipWithIndex.map { case (s, p) => p.U < io.pushCount && bankOf(s) === b.U }
    when(hits.reduce(_ || _)) {
      mem.write(rowAddr(Mux1H(hits, slots)), Mux1H(hits, io.pushVals))
    }
  }
  private val popSlot = io.sp.pad(slotBits) - 1.U
  private val reads = mems.zipWithIndex.map { case (mem, b) => mem.read(rowAddr(popSlot), io.pop && bankOf(popSlot) === b.U) }
  private val popBankReg = RegEnable(bankOf(popSlot), io.pop)
  io.popVal := VecInit(reads)(popBankReg)
}
