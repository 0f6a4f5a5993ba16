package rtaccel.axi

import scala.collection.mutable
import scala.util.Random

/** Settings of the AXI4 slave memory model: latency (cycles from the address
  * handshake to the first beat, drawn uniformly from [latMin, latMax]) and the
  * chance each channel is not ready / not valid in a cycle (back-pressure).
  * One R beat per cycle at most: 64 B per 200 MHz cycle = 12.8 GB/s, the PL DDR3's peak.
  */
final case class AxiMemParams(latMin: Int = 20, latMax: Int = 20, stall: Double = 0.0, reorder: Boolean = true)

/** A Scala AXI4 slave with byte memory, for single-threaded chiseltest loops:
  * `cycle` takes what the master drives this cycle and returns what the slave
  * drives, then `commit` applies the handshakes. It checks the master's side of
  * the protocol (payload stable while valid and not ready, INCR, full-width
  * beats, len <= 255, no 4 KB crossing, W beats and wlast per AW) and fails at
  * once naming the cycle. Reads are answered out of order across IDs (in order
  * within one ID) when `reorder` is set.
  */
final class AxiMemModel(val mem: Array[Byte], p: AxiMemParams, rnd: Random, beatBytes: Int = 64) {
  final case class Addr(id: Int, addr: Long, len: Int, size: Int, burst: Int)
  private final class Burst(val a: Addr, val readyAt: Long) { var beat = 0 }
  private val reads = mutable.ArrayBuffer.empty[Burst]
  private val writes = mutable.Queue.empty[Burst]
  private val bq = mutable.Queue.empty[(Int, Long)]
  private var current: Option[Burst] = None
  private var now = 0L
  private var lastAr, lastAw: Option[Addr] = None
  private var lastW: Option[BigInt] = None
  var readBeats, writeBeats = 0L

  private def fail(what: String): Nothing = throw new AssertionError(s"AXI cycle $now: $what")
  private def check(a: Addr, ch: String): Unit = {
    if (a.burst != 1) fail(s"$ch burst ${a.burst}, expected INCR (1)")
    if ((1 << a.size) != beatBytes) fail(s"$ch size ${a.size}, expected full-width beats of $beatBytes bytes")
    if (a.len > 255) fail(s"$ch len ${a.len} > 255")
    if (a.addr % beatBytes != 0) fail(s"$ch address 0x${a.addr.toHexString} not beat-aligned")
    val end = a.addr + (a.len + 1L) * beatBytes - 1
    if (a.addr / 4096 != end / 4096) fail(s"$ch burst 0x${a.addr.toHexString}+${a.len + 1} beats crosses a 4 KB boundary")
    if (end >= mem.length) fail(s"$ch burst 0x${a.addr.toHexString}..0x${end.toHexString} past the memory (${mem.length} bytes)")
  }
  private def latency = p.latMin + rnd.nextInt(p.latMax - p.latMin + 1)
  private def go: Boolean = !(p.stall > 0 && rnd.nextDouble() < p.stall)

  // What the slave drives this cycle (decided before the master's payloads are seen).
  var arReady, awReady, wReady = false
  var rOut: Option[(Int, BigInt, Boolean)] = None // id, data, last
  var bOut: Option[Int] = None

  /** Decides this cycle's slave outputs. */
  def drive(): Unit = {
    arReady = go; awReady = go; wReady = go && writes.nonEmpty // W beats follow accepted AWs (a slave may wait for AW)
    if (current.isEmpty) {
      // Heads per ID, ready ones; pick at random among them (reordering across IDs).
      val heads = reads.groupBy(_.a.id).values.map(_.head).filter(_.readyAt <= now).toSeq
      if (heads.nonEmpty) current = Some(if (p.reorder) heads(rnd.nextInt(heads.size)) else heads.minBy(_.readyAt))
    }
    rOut = current.filter(_ => go).map { b =>
      val at = (b.a.addr + b.beat.toLong * beatBytes).toInt
      val data = BigInt(1, mem.slice(at, at + beatBytes).reverse)
      (b.a.id, data, b.beat == b.a.len)
    }
    bOut = bq.headOption.filter(_._2 <= now).filter(_ => go).map(_._1)
  }

  /** Applies the handshakes of this cycle: the master's valids, payloads (None when not valid) and readies. */
  def commit(ar: Option[Addr], aw: Option[Addr], w: Option[(BigInt, BigInt, Boolean)], rReady: Boolean, bReady: Boolean): Unit = {
    for (a <- lastAr) if (!ar.contains(a)) fail(s"AR payload changed or valid dropped before arready: $a -> $ar")
    for (a <- lastAw) if (!aw.contains(a)) fail(s"AW payload changed or valid dropped before awready: $a -> $aw")
    for (d <- lastW) if (!w.exists(x => wKey(x) == d)) fail("W payload changed or valid dropped before wready")
    lastAr = ar.filter(_ => !arReady); lastAw = aw.filter(_ => !awReady); lastW = w.filter(_ => !wReady).map(wKey)
    for (a <- ar if arReady) { check(a, "AR"); reads += new Burst(a, now + latency) }
    for (a <- aw if awReady) { check(a, "AW"); writes.enqueue(new Burst(a, 0)) }
    for ((data, strb, last) <- w if wReady) {
      val b = writes.head
      val at = (b.a.addr + b.beat.toLong * beatBytes).toInt
      for (k <- 0 until beatBytes if strb.testBit(k)) mem(at + k) = ((data >> (8 * k)) & 0xff).toByte
      if (last != (b.beat == b.a.len)) fail(s"wlast $last on beat ${b.beat} of a ${b.a.len + 1}-beat burst")
      b.beat += 1
      writeBeats += 1
      if (b.beat > b.a.len) { writes -= b; bq.enqueue((b.a.id, now + latency)) }
    }
    for ((id, _, _) <- rOut if rReady) {
      val b = current.get
      b.beat += 1
      readBeats += 1
      if (b.beat > b.a.len) { reads -= b; current = None }
    }
    if (bOut.isDefined && bReady) bq.dequeue()
    now += 1
  }
  private def wKey(w: (BigInt, BigInt, Boolean)): BigInt = (w._1 << 66) | (w._2 << 1) | (if (w._3) 1 else 0)

  def idle: Boolean = reads.isEmpty && writes.isEmpty && bq.isEmpty
}

object AxiMemModel {
  /** The PL DDR3 at a 200 MHz fabric clock: 100 ns = 20 cycles, 64 B per cycle (12.8 GB/s). */
  val ddr: AxiMemParams = AxiMemParams(latMin = 20, latMax = 20)
}
