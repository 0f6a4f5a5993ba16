package rtaccel.system

import chisel3._

/** A 64-byte line of 32-byte records to write (two hit records): `addr` is a
  * byte address, 64-byte aligned (its low six bits are ignored); `data`
  * little-endian, byte 0 in bits 7..0; `halves` which records to write (bit h:
  * bytes 32 h .. 32 h + 31), one or both.
  */
class WriteRecord(sys: SystemConfig) extends Bundle {
  val addr = UInt(sys.axiAddrBits.W)
  val data = UInt((WriteRecord.Bytes * 8).W)
  val halves = UInt(WriteRecord.Records.W)
}
object WriteRecord {
  val Bytes = 64

  /** The records of a line: 32 bytes each (SystemConfig.HitBytes). */
  val Records = 2
  val RecordBytes = Bytes / Records
}

/** Loading an on-chip store, the node store or the triangle store (MemoryFabric's side): a `start` pulse
  * copies `bytes` bytes at `base` (64-byte aligned: the node array's start)
  * from DRAM into the store, clamped to its capacity. Until `done`, every
  * node read goes to DRAM; `done` stays high until the next `start`. A
  * `start` while `busy` is ignored.
  * `storedBytes`: how many bytes the store holds (reads below
  * base + storedBytes are served on chip).
  */
class NodeStoreLoad(addrBits: Int) extends Bundle {
  def this(sys: SystemConfig) = this(sys.axiAddrBits)
  val base = Input(UInt(addrBits.W))
  val bytes = Input(UInt(32.W))
  val start = Input(Bool())
  val busy = Output(Bool())
  val done = Output(Bool())
  val storedBytes = Output(UInt(32.W))
}

/** Event counters of the memory side, free-running from reset (a consumer
  * that clears its counters keeps a snapshot). 64 bits: no wrap in any run.
  */
class FabricStats extends Bundle {

  /** R beats received (every ID, node-store fill included). */
  val readBeats = UInt(64.W)

  /** W beats sent. */
  val writeBeats = UInt(64.W)

  /** Cycles with arvalid && !arready. */
  val arStallCycles = UInt(64.W)

  /** Node-client requests served by the node store. */
  val nodeStoreHits = UInt(64.W)

  /** Node-client requests sent to DRAM. */
  val nodeStoreMisses = UInt(64.W)

  /** Triangle-client requests served by the triangle store. */
  val triStoreHits = UInt(64.W)
}
