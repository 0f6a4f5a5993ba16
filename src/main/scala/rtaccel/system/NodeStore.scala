package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.Axi4Params
import rtaccel.mem.{MemPortParams, MemResponse}

/** The on-chip node store: the first `capacityBytes` bytes of the node array
  * (the top of the tree when nodes are in top-levels-first order, see
  * docs/node-store.md), copied from DRAM when a scene is loaded, then served
  * from block RAM at a fixed latency to `clients` node clients.
  *
  * Storage: words of max(record, beat) bytes, written a beat (one masked
  * lane) at a time by the fill. `copies` copies of the storage, each a true
  * dual-port BRAM (port A also takes the fill's writes, which only happen
  * while no client can hit). With at most two clients per copy each has a
  * port of its own; with more, a copy's clients share both its ports, each
  * port serving whichever is waiting (StorePort). More copies buy no waiting
  * at the price of the whole store's block RAM again.
  *
  * Fill: StoreFill (bursts with AXI ID `fillId`, 4 KB split, the 1024-bit
  * realignment), one whole line written per beat.
  *
  * A request hits when the store is loaded, its address is record-aligned
  * relative to `base`, and lies below base + storedBytes. Latency: request
  * accepted in cycle t, response offered from t + `NodeStore.Latency` = 3
  * (the request register, the BRAM read, then the output queue) on a port
  * of its own, one cycle more on a shared one. Full rate: one record per
  * port per cycle.
  */
class NodeStore(p: Axi4Params, port: MemPortParams, clients: Int, capacityBytes: Int, fillId: Int, copies: Int = 1)
    extends Module {
  require(
    copies >= 1 && copies <= (clients + 1) / 2,
    s"NodeStore: copies must be 1 to ceil(clients / 2) = ${(clients + 1) / 2}, got $copies"
  )
  private val B = p.beatBytes
  private val recBytes = port.recordBytes
  require(Integer.bitCount(recBytes) == 1, s"NodeStore: node records must be a power of two bytes, got $recBytes")
  private val wordBytes = recBytes.max(B)
  private val lanes = wordBytes / B
  require(
    capacityBytes > 0 && capacityBytes % wordBytes == 0,
    s"NodeStore: capacity $capacityBytes is not a positive multiple of $wordBytes bytes"
  )
  private val words = capacityBytes / wordBytes

  val io = IO(new StoreIO(p, port, clients))

  // ---- Fill ----
  private val fill = StoreFill(p, io, capacityBytes, wordBytes, fillId)
  private val errorReg = RegInit(false.B)
  io.error := errorReg || fill.io.error
  private val baseReg = fill.io.base

  // ---- Serve ----
  private val recBits = log2Ceil(recBytes)
  for (c <- 0 until clients) {
    val a = io.probe(c)
    val aligned = if (recBits == 0) true.B else a(recBits - 1, 0) === baseReg(recBits - 1, 0)
    io.hit(c) := fill.io.ready && a >= baseReg && a < fill.io.limit && aligned
  }
  private val mems = Seq.fill(copies)(SyncReadMem(words, Vec(lanes, UInt((8 * B).W))))
  private val wEnable = fill.io.write.valid
  private val wLine = fill.io.write.bits.line
  private val wWord = if (lanes == 1) wLine else wLine >> log2Ceil(lanes)
  private val wMask =
    VecInit((0 until lanes).map(l => if (lanes == 1) true.B else wLine(log2Ceil(lanes) - 1, 0) === l.U))
  private val wData = VecInit(Seq.fill(lanes)(fill.io.write.bits.data))

  for (g <- StorePort.assign(clients, copies)) {
    val mem = mems(g.copy)
    // The request's offset from the base is registered before the read: the subtraction and the block RAMs'
    // enables behind it were one path (docs/fmax.md).
    val sp = new StorePort(io, g.clients, (a: UInt) => a - baseReg, g.ports.size)
    val records = g.ports.zipWithIndex.map { case (port, i) =>
      val word = sp.s0Fields(i) >> log2Ceil(wordBytes)
      val read = sp.s0Valid(i)
      val rdata = if (port == 0) mem.readWrite(Mux(wEnable, wWord, word), wData, wMask, wEnable || read, wEnable)
      else mem.read(word, read)
      // A hit is only accepted when loaded, and the fill writes only while not loaded.
      when(read && wEnable) { errorReg := true.B }
      val s1SubReg = RegEnable(sp.s0Fields(i)(log2Ceil(wordBytes) - 1, 0), read)
      // The read data goes straight into the output queue (through the ports' select when clients share them),
      // with no register of its own: Yosys 0.23 would merge such a register into the memory's read port first and
      // leave the port's address register outside, so the shared read/write port would become a read port and a
      // write port, and the memory would be doubled to give the second client its read port (measured: 456
      // instead of 228 BRAM36 for 1 MiB). The BRAM's output is the read's register.
      if (recBytes >= B) rdata.asUInt else (rdata.asUInt >> (s1SubReg << 3))(8 * recBytes - 1, 0)
    }
    when(sp.answer(records)) { errorReg := true.B }
  }
}

object NodeStore {

  /** Request to response offered, in cycles: the request register, the BRAM read (its address register), then
    * the output queue.
    */
  val Latency = 3

  /** Output queue per client: the read in the pipeline + 1 more than it takes to see a dequeue, so a client that always takes keeps one per cycle. */
  val OutDepth: Int = Latency + 1

  /** Request to response offered on a port that several clients share (StorePort): the request's queue, then as
    * [[Latency]]. */
  val SharedLatency: Int = Latency + 1
}
