package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.Axi4Params
import rtaccel.mem.{MemPortParams, MemResponse}

/** The on-chip triangle store: the first `capacityBytes` bytes of the
  * triangle array (docs/scene-store.md), copied from DRAM when a scene is
  * loaded (after the node store), then served from block RAM at a fixed
  * latency to `clients` triangle clients, like NodeStore serves nodes.
  *
  * Records are `port.recordBytes` (48 for a triangle), at most one beat and a
  * multiple of 16 bytes, so a record starts on a 16-byte boundary of the
  * array and may straddle two lines (beats). Storage: line j of the array
  * (bytes j*B .. j*B+B-1, B the beat) lives in bank j mod 2 at index j / 2,
  * so the two lines a record touches, L and L+1, are always in different
  * banks: one read per bank per request (bank 0 at (L+1)/2, bank 1 at L/2),
  * then the pair is put in order and shifted down by the record's 16-byte
  * offset in line L. `copies` copies of the two banks, each true dual-port
  * BRAM (port A also takes the fill's writes, which only happen while no
  * client can hit); clients have ports of their own or share a copy's two
  * ports (StorePort), as in NodeStore.
  *
  * A request hits when the store is loaded, its address is 16-byte aligned
  * relative to `base` and the whole record lies below base + storedBytes.
  * Latency: request accepted in cycle t, response offered from t +
  * `TriStore.Latency` = 4 (the request register, the BRAM read, the ordered line pair's register, then the
  * record's shift into the output queue) on a port of its own, one cycle more on a shared one. Full rate: one record per port per
  * cycle.
  */
class TriStore(p: Axi4Params, port: MemPortParams, clients: Int, capacityBytes: Int, fillId: Int, copies: Int = 1)
    extends Module {
  require(
    copies >= 1 && copies <= (clients + 1) / 2,
    s"TriStore: copies must be 1 to ceil(clients / 2) = ${(clients + 1) / 2}, got $copies"
  )
  private val B = p.beatBytes
  private val recBytes = port.recordBytes
  require(
    recBytes % TriStore.Grain == 0 && recBytes <= B,
    s"TriStore: records must be a multiple of ${TriStore.Grain} bytes up to one $B-byte beat, got $recBytes"
  )
  require(
    Integer.bitCount(capacityBytes) == 1 && capacityBytes >= 2 * B,
    s"TriStore: capacity must be a power of two of at least two $B-byte lines, got $capacityBytes"
  )
  private val lines = capacityBytes / B
  private val words = lines / 2 // per bank
  private val idxBits = log2Ceil(words).max(1)
  private val lineBits = log2Ceil(B)
  private val grainBits = log2Ceil(TriStore.Grain)
  // A record's offset in its first line, in grains, and the bits of the line pair it can reach.
  private val subBits = lineBits - grainBits
  private val pairBits = 8 * (recBytes + B - TriStore.Grain)

  val io = IO(new StoreIO(p, port, clients))

  /** The record from a registered line pair, `Cat(offset, pair)`: the pair shifted down by the offset's grains. */
  private def shifted(d: UInt): UInt = {
    val sub = d(pairBits + subBits - 1, pairBits)
    (d(pairBits - 1, 0) >> (sub << (grainBits + 3)))(8 * recBytes - 1, 0)
  }

  // ---- Fill: whole lines (a record's second line is filled with the first) ----
  private val fill = StoreFill(p, io, capacityBytes, B, fillId)
  private val errorReg = RegInit(false.B)
  io.error := errorReg || fill.io.error
  private val baseReg = fill.io.base
  // The last address at which a whole record is stored, + 1: limit - (rec - 1), registered like the limit.
  // Below base when nothing whole is stored: no hit.
  // base + rec is registered first (a cycle later still), so its add and the compare are not one path.
  private val baseRecReg = RegNext(baseReg +& recBytes.U, 0.U)
  private val recLimitReg =
    RegNext(Mux(fill.io.limit >= baseRecReg, fill.io.limit - (recBytes - 1).U, 0.U), 0.U)
  // base - B, for bank 0's word index (below), registered the same way: only its low bits are read, so the
  // wrap below address 0 changes nothing.
  private val baseLessLineReg = RegNext(baseReg - B.U, 0.U)
  // recLimitReg is two registers behind the fill's limit and base; an empty fill is ready two cycles after its
  // start, so hits also wait until `ready` has held for two cycles (no hit is tested against a stale limit).
  private val settledReg = RegNext(RegNext(fill.io.ready, false.B), false.B)

  // ---- Serve ----
  for (c <- 0 until clients) {
    val a = io.probe(c)
    val aligned = a(grainBits - 1, 0) === baseReg(grainBits - 1, 0)
    io.hit(c) := fill.io.ready && settledReg && a >= baseReg && a < recLimitReg && aligned
  }
  private val banks = Seq.fill(copies)(Seq.fill(2)(SyncReadMem(words, UInt((8 * B).W))))
  private val wEnable = fill.io.write.valid
  private val wLine = fill.io.write.bits.line
  private val wIdx = (wLine >> 1)(idxBits - 1, 0)

  for (g <- StorePort.assign(clients, copies)) {
    // The request's offsets are registered before the read, as in NodeStore. Bank 0 holds the even line of L,
    // L+1, bank 1 the odd one. (L + 1) / 2 is (addr - (base - B)) / 2B: one subtraction, not a subtraction and
    // an increment. (L+1)/2 past the last word (L the last line, odd) wraps to word 0, a power of two: that line
    // is then not part of the record (it lies below the stored end).
    val sp = new StorePort(
      io,
      g.clients,
      (a: UInt) => VecInit(a - baseReg, a - baseLessLineReg),
      g.ports.size,
      TriStore.DataStages
    )
    val records = g.ports.zipWithIndex.map { case (port, i) =>
      val rel = sp.s0Fields(i)(0)
      val line = rel >> lineBits
      val idx = Seq((sp.s0Fields(i)(1) >> (lineBits + 1))(idxBits - 1, 0), (line >> 1)(idxBits - 1, 0))
      val read = sp.s0Valid(i)
      val rdata = banks(g.copy).zipWithIndex.map { case (mem, b) =>
        if (port == 0) {
          val w = wEnable && wLine(0) === b.U
          mem.readWrite(Mux(w, wIdx, idx(b)), fill.io.write.bits.data, w || read, w)
        } else mem.read(idx(b), read)
      }
      // A hit is only accepted when loaded, and the fill writes only while not loaded.
      when(read && wEnable) { errorReg := true.B }
      val s1OddReg = RegEnable(line(0), read)
      val s1SubReg = RegEnable(rel(lineBits - 1, grainBits), read)
      // The two lines are put in order (line L+1 above line L) and registered with the record's offset by the
      // StorePort's data stage, which shifts the record down after it. Not a register straight on the read data:
      // Yosys would fold it into the memory (as in NodeStore), so a LUT lies in front of it. Into the answer
      // queue in one cycle, the BRAM's 2.46 ns clock-to-out, the read-during-write bypass Yosys adds on port B
      // (the fill writes on port A), the order and the shift were 5.16 ns (docs/fmax.md). Only the pair's bytes
      // that a record can reach are registered.
      val pair = Mux(s1OddReg, Cat(rdata(0), rdata(1)), Cat(rdata(1), rdata(0)))
      Cat(s1SubReg, pair(pairBits - 1, 0))
    }
    when(sp.answer(records, shifted)) { errorReg := true.B }
  }
}

object TriStore {

  /** Record alignment inside the array: a 48-byte triangle starts on a 16-byte boundary. */
  val Grain = 16

  /** The registers on a read's ordered line pair before the record's shift (StorePort's data stages). */
  val DataStages = 1

  /** Request to response offered, in cycles, on a port of its own: NodeStore's, and the record's register. */
  val Latency: Int = NodeStore.Latency + DataStages

  /** The same on a port that several clients share (the request's queue first). */
  val SharedLatency: Int = NodeStore.SharedLatency + DataStages
}
