package rtaccel.sim.axi

import scala.collection.mutable
import scala.util.Random
import rtaccel.axi.Axi4
import rtaccel.sim.mem.{DramModel, Latency}

/** An AXI4 slave memory for chiseltest, cycle by cycle and single-threaded.
  *
  * Each cycle, in this order (AxiMemoryHarness does it for an Axi4Master bundle):
  *  1. `slave`: the slave's outputs for this cycle (readies, R and B offers); poke them;
  *  2. `commit(master)`: the master's outputs sampled after the pokes settle; the
  *     model checks the protocol, then takes every handshake that fired;
  *  3. step the clock, then `tick()`.
  *
  * Timing: every burst (read or write) is a transfer on a DramModel, so it
  * waits its latency (drawn per burst, uniform in `latency` ns at the DDR's
  * clock) and its bytes share the DRAM's 12.8 GB/s with all other bursts,
  * charged whole 64-byte bursts. A read burst's beats are offered once its
  * transfer is done; a write is answered on B once its data is in and its
  * transfer is done.
  *
  * Back-pressure and order (seeded): arready, awready and wready are each high
  * with probability `readyProb` (and low at `maxReads` / `maxWrites`); a ready
  * R beat or B response is offered with probability `validProb`; with
  * `reorder`, a random ID's oldest ready burst goes next (in order within an
  * ID); with `interleave`, R beats of different IDs interleave.
  *
  * Protocol checks (an AxiProtocolError at once): AR/AW/W payload stable and
  * valid held while valid && !ready; INCR bursts of full-width, aligned beats;
  * len <= 255; no burst crossing 4 KB; wlast on exactly the last beat of its
  * burst. Writes go to `mem` (with strobes) when their beat is taken; reads
  * read `mem` when the beat is offered.
  */
final class AxiMemoryModel(val params: AxiMemoryParams, val mem: SparseMemory = new SparseMemory) {
  private val B = params.beatBytes
  private val rnd = new Random(params.seed)
  private val dram = new DramModel(params.ddr.bytesPerCycle, params.ddr.device.burstBytes)
  private val latency = params.latency.cycles(params.clock)
  private def drawLatency(): Int = latency match {
    case Latency.Fixed(c)        => c
    case Latency.Uniform(lo, hi) => lo + rnd.nextInt(hi - lo + 1)
  }
  private var now = 0L
  private var seq = 0L

  private final class Burst(val seq: Long, val a: AxiAddrBeat, val resp: Int) {
    val beats: Int = a.len + 1
    var moved = false // the DRAM transfer is done
    var beatsDone = 0 // R beats sent, or W beats taken
  }
  private val reads = mutable.ArrayBuffer.empty[Burst] // accepted, not fully sent; in acceptance order
  private val awWait = mutable.Queue.empty[Burst] // write addresses waiting for their data
  private val wEarly = mutable.Queue.empty[AxiWBeat] // W beats before their AW
  private val writes = mutable.ArrayBuffer.empty[Burst] // data in, waiting for DRAM or for B
  private val byId = mutable.HashMap.empty[Long, Burst]
  private val client = new DramModel.Client {
    def inOrder = false
    def completed(id: Long): Unit = byId.remove(id).foreach(_.moved = true)
  }

  // This cycle's outputs, drawn once; an offer not taken is held.
  private var drawnAt = -1L
  private var out = AxiSlaveSignals(false, false, false, None, None)
  private var offerR: Option[Burst] = None
  private var offerB: Option[Burst] = None
  // The master's requests waiting for ready in the previous cycle (must be held unchanged).
  private var heldAr, heldAw: Option[AxiAddrBeat] = None
  private var heldW: Option[AxiWBeat] = None

  var readBursts, readBeats, writeBursts, writeBeats, reorderedBursts, interleavedBeats = 0L
  private var lastRBurst: Option[Burst] = None

  def cycle: Long = now

  /** No burst accepted and unanswered. */
  def idle: Boolean = reads.isEmpty && awWait.isEmpty && wEarly.isEmpty && writes.isEmpty

  def slave: AxiSlaveSignals = {
    if (drawnAt != now) {
      drawnAt = now
      if (offerR.isEmpty && rnd.nextDouble() < params.validProb) offerR = pickRead()
      if (offerB.isEmpty && rnd.nextDouble() < params.validProb) offerB = pickWrite()
      val r = offerR.map(b =>
        AxiRBeat(
          b.a.id,
          SparseMemory.toLE(mem.read(b.a.addr + b.beatsDone.toLong * B, B)),
          b.resp,
          b.beatsDone == b.beats - 1
        )
      )
      out = AxiSlaveSignals(
        arReady = reads.size < params.maxReads && rnd.nextDouble() < params.readyProb,
        awReady = awWait.size + writes.size < params.maxWrites && rnd.nextDouble() < params.readyProb,
        wReady = rnd.nextDouble() < params.readyProb,
        r = r,
        b = offerB.map(b => AxiBResp(b.a.id, b.resp))
      )
    }
    out
  }

  private def pickRead(): Option[Burst] = {
    val unfinished = reads // a burst leaves `reads` with its last beat
    val streaming = unfinished.find(b => b.beatsDone > 0)
    val heads = unfinished.groupBy(_.a.id).values.map(_.minBy(_.seq)).filter(_.moved).toSeq.sortBy(_.seq)
    val eligible =
      if (!params.interleave && streaming.isDefined) streaming.filter(_.moved).toSeq
      else if (!params.reorder) heads.take(1).filter(h => unfinished.headOption.contains(h))
      else heads
    if (eligible.isEmpty) None else Some(eligible(rnd.nextInt(eligible.size)))
  }
  private def pickWrite(): Option[Burst] = {
    val heads = writes.groupBy(_.a.id).values.map(_.minBy(_.seq)).filter(_.moved).toSeq.sortBy(_.seq)
    val eligible = if (params.reorder) heads else heads.take(1).filter(h => writes.headOption.contains(h))
    if (eligible.isEmpty) None else Some(eligible(rnd.nextInt(eligible.size)))
  }

  private def fail(what: String): Nothing = throw new AxiProtocolError(s"AXI protocol, cycle $now: $what")

  private def checkAddr(ch: String, a: AxiAddrBeat): Unit = {
    if (a.burst != Axi4.BurstIncr) fail(s"$ch burst type ${a.burst}, expected INCR (1): $a")
    if (a.size != Integer.numberOfTrailingZeros(B))
      fail(s"$ch size ${a.size}, expected full-width beats (${Integer.numberOfTrailingZeros(B)}): $a")
    if (a.len < 0 || a.len > 255) fail(s"$ch len ${a.len} outside 0..255: $a")
    if (a.addr % B != 0) fail(s"$ch address 0x${a.addr.toHexString} not aligned to the $B-byte beat: $a")
    if ((a.addr % Axi4.BoundaryBytes) + (a.len + 1).toLong * B > Axi4.BoundaryBytes)
      fail(s"$ch burst of ${a.len + 1} beats at 0x${a.addr.toHexString} crosses a 4 KB boundary: $a")
  }
  private def checkHeld[T](ch: String, held: Option[T], now: Option[T]): Unit = held.foreach { h =>
    if (now.isEmpty) fail(s"$ch valid dropped before ready (was $h)")
    if (!now.contains(h)) fail(s"$ch payload changed while valid && !ready: was $h, now ${now.get}")
  }

  def commit(m: AxiMasterSignals): Unit = {
    val s = slave
    checkHeld("AR", heldAr, m.ar); checkHeld("AW", heldAw, m.aw); checkHeld("W", heldW, m.w)
    m.ar.foreach(checkAddr("AR", _))
    m.aw.foreach(checkAddr("AW", _))
    heldAr = m.ar.filter(_ => !s.arReady)
    heldAw = m.aw.filter(_ => !s.awReady)
    heldW = m.w.filter(_ => !s.wReady)

    if (m.ar.isDefined && s.arReady) {
      val a = m.ar.get
      val b = new Burst(seq, a, if (params.errorAt(a.addr)) 2 else 0)
      seq += 1
      reads += b
      byId(b.seq) = b
      dram.issue(client, b.seq, a.addr, b.beats * B, drawLatency(), now)
      readBursts += 1
    }
    if (m.aw.isDefined && s.awReady) {
      val a = m.aw.get
      awWait.enqueue(new Burst(seq, a, if (params.errorAt(a.addr)) 2 else 0))
      seq += 1
      writeBursts += 1
    }
    if (m.w.isDefined && s.wReady) { wEarly.enqueue(m.w.get); writeBeats += 1 }
    while (awWait.nonEmpty && wEarly.nonEmpty) {
      val b = awWait.head
      val w = wEarly.dequeue()
      val base = b.a.addr + b.beatsDone.toLong * B
      for (i <- 0 until B if w.strb.testBit(i)) mem.write(base + i, Array(((w.data >> (8 * i)) & 0xff).toByte))
      b.beatsDone += 1
      val lastExpected = b.beatsDone == b.beats
      if (w.last != lastExpected)
        fail(s"wlast ${w.last} on beat ${b.beatsDone} of ${b.beats} of the write burst ${b.a}")
      if (lastExpected) {
        awWait.dequeue()
        writes += b
        byId(b.seq) = b
        dram.issue(client, b.seq, b.a.addr, b.beats * B, drawLatency(), now)
      }
    }

    if (s.r.isDefined && m.rReady) {
      val b = offerR.get
      if (reads.head ne b) { if (b.beatsDone == 0) reorderedBursts += 1 }
      if (lastRBurst.exists(l => (l ne b) && l.beatsDone > 0 && l.beatsDone < l.beats)) interleavedBeats += 1
      lastRBurst = Some(b)
      b.beatsDone += 1
      readBeats += 1
      if (b.beatsDone == b.beats) reads -= b
      offerR = None
    }
    if (s.b.isDefined && m.bReady) {
      writes -= offerB.get
      offerB = None
    }
  }

  def tick(): Unit = {
    dram.tick(now)
    now += 1
  }
}
