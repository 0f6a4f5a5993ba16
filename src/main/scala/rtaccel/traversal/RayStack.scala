package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig

/** Every ray's traversal stack in one on-chip memory: ray `id`'s entry `sp`
  * lives at `id * stackDepth + sp`, so stacks of different rays can never
  * overlap (the seed's code addressed them wrongly).
  *
  * One access per cycle, as TraversalControl handles one ray per cycle: a
  * push writes, a pop reads, and the popped value appears the next cycle.
  * Synchronous read so that it maps onto block RAM.
  */
class RayStack(cfg: AccelConfig) extends Module {
  val io = IO(new Bundle {
    val en      = Input(Bool())
    val isPush  = Input(Bool())
    val rayId   = Input(UInt(cfg.rayIdBits.W))
    /** Entry index within the ray's stack: the slot written, or the slot read. */
    val slot    = Input(UInt(log2Ceil(cfg.stackDepth).max(1).W))
    val pushVal = Input(UInt(cfg.nodeIndexBits.W))
    /** The entry read by a pop in the previous cycle. */
    val popVal  = Output(UInt(cfg.nodeIndexBits.W))
  })
  override def desiredName = s"RayStack_n${cfg.numRayIds}_d${cfg.stackDepth}"

  private val entries = cfg.numRayIds * cfg.stackDepth
  private val mem = SyncReadMem(entries, UInt(cfg.nodeIndexBits.W))
  private val addr = io.rayId * cfg.stackDepth.U + io.slot
  io.popVal := mem.read(addr, io.en && !io.isPush)
  when(io.en && io.isPush) { mem.write(addr, io.pushVal) }
}
