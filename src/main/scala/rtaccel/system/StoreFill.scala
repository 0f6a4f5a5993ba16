package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4, Axi4Addr, Axi4Params, Axi4R, ByteRotate}

/** The fill of an on-chip store (NodeStore, TriStore): on `load.start`,
  * copies the first `capacityBytes` bytes at `load.base` (or `load.bytes`,
  * rounded up to whole `wordBytes` words, if fewer) from DRAM, and hands each
  * `B`-byte line (one beat, B = the m_axi beat) to the store as a write of
  * line j (the store's bytes j*B ..).
  *
  * Bursts of up to `FillBurstBeats` beats with AXI ID `fillId`, never
  * crossing 4 KB, at most `FillBursts` outstanding (a bound so the fill
  * cannot flood the slave's queues; 8 x 16 beats cover DRAM latency). Beats
  * of one ID arrive in order, so a line counter places them. Every beat that
  * reaches `r` must be one this fill asked for (the fabric routes the fill ID
  * to the busy store): a beat while idle, or a non-OKAY one, sets `error`
  * (a non-OKAY beat still counts, so the fill ends).
  *
  * A beat wider than the base's 64-byte alignment (a 1024-bit m_axi: the
  * image's node array starts at offset 64) is read from the beat-aligned
  * address below `base`: with `off` = base mod beat, line j (store bytes
  * j*B ..) is beat j's bytes from `off` on, then beat j+1's first `off`
  * bytes, so each beat, rotated right by `off`, completes the line before
  * it, one extra beat at the end. Every write is still one whole line, so
  * the storage maps to block RAM as before. A base that is not 64-byte
  * aligned sets `error` (the contract's alignment).
  *
  * Serving: `ready` (loaded, and no new load starting this cycle) and a
  * request in [`base`, `limit`) (`limit` = base + the stored bytes,
  * registered) may be served on chip; the fill writes only while not loaded.
  */
class StoreFill(p: Axi4Params, capacityBytes: Int, wordBytes: Int, fillId: Int) extends Module {
  private val B = p.beatBytes
  private val beatBits = log2Ceil(B)
  require(
    wordBytes % B == 0 && Integer.bitCount(wordBytes / B) == 1,
    s"StoreFill: a word ($wordBytes bytes) must be a power-of-two number of $B-byte beats"
  )
  private val lanes = wordBytes / B
  require(
    capacityBytes > 0 && capacityBytes % wordBytes == 0,
    s"StoreFill: capacity $capacityBytes is not a positive multiple of $wordBytes bytes"
  )
  private val words = capacityBytes / wordBytes
  private val lines = capacityBytes / B

  /** The beat is wider than the base's alignment: the fill reads one beat more and realigns (above). */
  private val realign = B > StoreFill.BaseAlign

  /** Counts of beats: the lines, and the realigning fill's extra beat. */
  private val lineBits = log2Ceil(lines + (if (realign) 2 else 1))

  val io = IO(new Bundle {
    val load = new NodeStoreLoad(p.addrBits)
    val ar = Decoupled(new Axi4Addr(p))

    /** R beats with ID `fillId` routed here; always taken. */
    val r = Flipped(Valid(new Axi4R(p)))
    val error = Output(Bool())
    val ready = Output(Bool())
    val base = Output(UInt(p.addrBits.W))
    val limit = Output(UInt((p.addrBits + 1).W))

    /** One whole line to write: line `line` of the store, `data` its B bytes. */
    val write = Valid(new Bundle {
      val line = UInt(lineBits.W)
      val data = UInt((8 * B).W)
    })
  })

  private val baseReg = RegInit(0.U(p.addrBits.W))
  private val totalReg = RegInit(0.U(lineBits.W)) // lines to fill
  private val leftReg = RegInit(0.U(lineBits.W)) // lines not yet asked for
  // Beats asked for and not yet received, and whether there are any: registers, so a beat's check is not a
  // compare of two line counts (with it, the beat's check into the bursts' count was the fill's longest path,
  // docs/fmax.md). An AR asks for at least one beat, and a beat is taken only while one is outstanding, so
  // after an AR some are; after a beat alone, some are unless it was the only one.
  private val askedReg = RegInit(0.U(lineBits.W))
  private val askedAnyReg = RegInit(false.B)
  private val receivedReg = RegInit(0.U(lineBits.W))
  private val burstsReg = RegInit(0.U(log2Ceil(StoreFill.FillBursts + 1).W))
  private val busyReg = RegInit(false.B)
  private val loadedReg = RegInit(false.B)
  private val errorReg = RegInit(false.B)
  // A start while a fill runs is ignored: beats of its bursts are still on the way.
  private val startNow = io.load.start && !busyReg
  // The base's offset in its beat, in whole 64-byte lines (0 unless `realign`).
  private val alignBits = log2Ceil(StoreFill.BaseAlign)
  private val offReg = Option.when(realign)(RegInit(0.U((beatBits - alignBits).W)))
  private val storedLinesReg = Option.when(realign)(RegInit(0.U(lineBits.W)))
  // The fill is sized in the two cycles after its start, from the registered byte count (`sizingReg`, then
  // `sizedReg`): no burst is prepared and the fill cannot end in them. The count's compare, round-up and the
  // registers it loads were one path from the load port, and then, from `bytesReg`, the round-up's carry chain
  // and the clamp in front of the line counts' multiplexers (docs/fmax.md): the round-up and the clamp's compare
  // are registered (`roundUpReg`, `overReg`) in the first cycle and the counts loaded from them in the second.
  private val bytesReg = RegInit(0.U(io.load.bytes.getWidth.W))
  private val sizingReg = RegInit(false.B)
  private val sizedReg = RegInit(false.B)
  // Whole words (a record never straddles the end), at most the capacity: ceil(bytes / wordBytes) is more than
  // `words` exactly when bytes is more than the capacity, so the clamp compares `bytes` with a constant beside the
  // round-up, whose add then needs only the bits of a count up to `words`. Both registers follow `bytesReg` every
  // cycle, without an enable: it changes only at a start, two cycles before they are read.
  private val wordBits = log2Ceil(wordBytes)
  private val overReg = RegNext(bytesReg > capacityBytes.U, false.B)
  private val roundUpReg = RegNext(
    ((bytesReg >> wordBits)(lineBits - 1, 0) +& bytesReg(wordBits - 1, 0).orR.asUInt)(lineBits - 1, 0),
    0.U
  )
  when(startNow) {
    bytesReg := io.load.bytes
    sizingReg := true.B
    baseReg := io.load.base
    offReg.foreach(_ := io.load.base(beatBits - 1, alignBits))
    if (realign) when(io.load.base(alignBits - 1, 0) =/= 0.U) { errorReg := true.B }
    leftReg := 0.U
    askedReg := 0.U
    askedAnyReg := false.B
    receivedReg := 0.U
    busyReg := true.B
    loadedReg := false.B
  }
  when(sizingReg) {
    sizingReg := false.B
    sizedReg := true.B
  }
  when(sizedReg) {
    val ws = Mux(overReg, words.U, roundUpReg)
    val total = offReg.fold(ws << log2Ceil(lanes))(o => (ws << log2Ceil(lanes)) +& (o =/= 0.U).asUInt)
    totalReg := total
    leftReg := total
    storedLinesReg.foreach(_ := ws << log2Ceil(lanes))
    sizedReg := false.B
  }
  // The next burst is sized a cycle before it is offered and waits in arAddrReg/arBeatsReg. A burst is prepared
  // only while none waits, and counted in burstsReg when it leaves, so at most FillBursts are outstanding.
  private val fillAddrReg = RegInit(0.U(p.addrBits.W)) // the next burst's address: base + issued beats
  private val arPendReg = RegInit(false.B)
  private val arAddrReg = Reg(UInt(p.addrBits.W))
  private val burstBits = log2Ceil(StoreFill.FillBurstBeats + 1)
  private val arBeatsReg = Reg(UInt(burstBits.W))
  // Its size comes from registers: the beats not yet asked for (total - issued), and their minimum with a burst
  // a cycle behind it; a burst is sized only once that minimum has caught up (`settledReg`: no start, sizing or AR
  // in the cycle before).
  // The 4 KB room, capped at a burst, is a table of the address's beat-in-page bits (one LUT per bit). No
  // subtraction or carry-chain compare lies before the burst's size (docs/fmax.md).
  private val burstCap = StoreFill.FillBurstBeats.U(burstBits.W)
  private val leftCapReg = RegNext(Mux(leftReg > burstCap, burstCap, leftReg.pad(burstBits)(burstBits - 1, 0)), 0.U)
  private val settledReg = RegNext(!(startNow || sizingReg || sizedReg || io.ar.fire), false.B)
  private val pageBits = log2Ceil(Axi4.BoundaryBytes)
  private val pageBeats = Axi4.BoundaryBytes / B
  private val room =
    VecInit(Seq.tabulate(pageBeats)(q => (pageBeats - q).min(StoreFill.FillBurstBeats).U(burstBits.W)))(
      fillAddrReg(pageBits - 1, beatBits)
    )
  private val beats = Mux(leftCapReg < room, leftCapReg, room)
  when(busyReg && !arPendReg && settledReg && leftReg =/= 0.U && burstsReg =/= StoreFill.FillBursts.U) {
    arPendReg := true.B
    arAddrReg := fillAddrReg
    arBeatsReg := beats
  }
  io.ar.valid := arPendReg
  io.ar.bits := Axi4Addr.incr(p, fillId.U, arAddrReg, arBeatsReg)
  when(io.ar.fire) {
    arPendReg := false.B
    leftReg := leftReg - arBeatsReg
    fillAddrReg := fillAddrReg + (arBeatsReg << beatBits)
  }
  when(startNow) {
    fillAddrReg := (if (realign) Cat(io.load.base(p.addrBits - 1, beatBits), 0.U(beatBits.W)) else io.load.base)
    arPendReg := false.B
  }
  // A beat with a non-OKAY response is still counted and stored (its data is whatever the slave sent), so the
  // fill completes and the load ends at once; `error` (STATUS.AXI_ERROR) says the store is not to be trusted.
  // Left uncounted, the fill would wait for a beat that never comes, until the watchdog.
  private val beatOk = busyReg && askedAnyReg
  when(io.r.valid && (!beatOk || io.r.bits.resp =/= 0.U)) { errorReg := true.B }
  private val fillWrite = io.r.valid && beatOk
  burstsReg := burstsReg + io.ar.fire.asUInt - (fillWrite && io.r.bits.last).asUInt
  when(!startNow) {
    askedReg := askedReg + Mux(io.ar.fire, arBeatsReg, 0.U) - fillWrite.asUInt
    askedAnyReg := io.ar.fire || Mux(fillWrite, askedReg =/= 1.U, askedAnyReg)
  }
  when(fillWrite) { receivedReg := receivedReg + 1.U }
  when(busyReg && !sizingReg && !sizedReg && receivedReg === totalReg) {
    busyReg := false.B
    loadedReg := true.B
  }
  // Stage the beat: the write happens the cycle after it arrives.
  private val wValidReg = RegNext(fillWrite, false.B)
  private val wLineReg = RegEnable(receivedReg, fillWrite)
  private val wDataReg = RegEnable(io.r.bits.data, fillWrite)
  io.load.busy := busyReg
  io.load.done := loadedReg
  // Lines held: the beats read, but the realigning fill's extra one.
  private val storedBytes = storedLinesReg.getOrElse(totalReg) << beatBits
  io.load.storedBytes := Mux(loadedReg, storedBytes, 0.U)
  io.error := errorReg
  io.ready := loadedReg && !startNow
  io.base := baseReg
  // The end of the stored bytes, registered: it follows baseReg and totalReg a
  // cycle late, and a hit needs `ready`, set only when the fill is done, many
  // cycles after both were loaded. So the stores' hit tests are compares side
  // by side, not a subtraction then a compare.
  io.limit := RegNext(baseReg +& storedBytes, 0.U)

  // The line a staged beat writes and its bytes: the beat itself, or (realigning) the line before it, completed.
  offReg match {
    case None =>
      io.write.valid := wValidReg
      io.write.bits.line := wLineReg
      io.write.bits.data := wDataReg
    case Some(off) =>
      val rot = ByteRotate.right(wDataReg, Cat(off, 0.U(alignBits.W)))
      val prevReg = RegEnable(rot, wValidReg)
      // Bytes below B - off of the line come from the beat before (rotated), the rest from this one.
      val keep = (0 until B).map(j => Cat(off, 0.U(alignBits.W)) +& j.U < B.U)
      val merged = Cat((0 until B).reverse.map(j => Mux(keep(j), prevReg(8 * j + 7, 8 * j), rot(8 * j + 7, 8 * j))))
      val shifted = off =/= 0.U
      io.write.valid := wValidReg && !(shifted && wLineReg === 0.U)
      io.write.bits.line := Mux(shifted, wLineReg - 1.U, wLineReg)
      io.write.bits.data := Mux(shifted, merged, wDataReg)
  }
}

object StoreFill {

  /** The fill of the store whose ports are `io`, wired to them (load, AR, R); the store serves from its `write`s. */
  def apply(p: Axi4Params, io: StoreIO, capacityBytes: Int, wordBytes: Int, fillId: Int): StoreFill = {
    val fill = Module(new StoreFill(p, capacityBytes, wordBytes, fillId))
    fill.io.load <> io.load
    io.ar <> fill.io.ar
    fill.io.r := io.r
    fill
  }
  val FillBurstBeats = 16
  val FillBursts = 8

  /** A store's base alignment in DDR (NodeStoreLoad: `base` is 64-byte aligned). */
  val BaseAlign = 64
}
