package rtaccel.mem

import rtaccel.scene.MemoryImage

import scala.collection.mutable
import scala.util.Random

/** The memory behind one accelerator port, cycle by cycle, for tests and the
  * regression. It serves `recordBytes`-byte records of a memory image.
  *
  * Protocol, once per simulated cycle, mirroring a ready/valid port:
  *  1. `reqReady(addr)`: may the DUT's pending request be accepted now?
  *     (`stalled()` records a cycle where a valid request was refused);
  *  2. `accept(addr, tag)` when the request fires;
  *  3. `response`: the response on offer, if any; `responseTaken()` when it fires;
  *  4. `tick()` ends the cycle.
  *
  * Without a cache, each request is one DRAM transfer of the record. With a
  * cache, a request needs every line its record touches (a 48-byte record can
  * straddle two lines): present lines hit, lines already being fetched merge
  * into their MSHR, other lines take a free MSHR and one DRAM line transfer.
  * A request needing more MSHRs than are free is refused until some retire.
  */
final class MemorySystemModel(image: MemoryImage, recordBytes: Int, params: MemoryParams, name: String) {
  private val rnd  = new Random(params.seed)
  private val dram = new DramModel(params.latency, params.bytesPerCycle, params.inOrder, rnd)

  /** `data` is read once, on acceptance (memory is read-only during a run). */
  private final class Req(val seq: Long, val tag: Int, val data: BigInt, var waitingLines: Int) {
    var readyAt: Long = Long.MaxValue
    var available: Boolean = false
  }
  private var now: Long = 0
  private var nextSeq: Long = 0
  private val outstanding = mutable.LinkedHashMap.empty[Long, Req] // accepted, not yet answered; in seq order
  private val ready = mutable.Queue.empty[Req]                     // out-of-order mode: available, in order of readiness
  private val hitPipe = mutable.Queue.empty[Req]                   // cache hits, ready at readyAt

  // Cache state: per set, line addresses in LRU order (head = least recent).
  private val sets  = params.cache.map(c => Array.fill(c.sets)(mutable.ArrayBuffer.empty[Long]))
  private val mshrs = mutable.LinkedHashMap.empty[Long, mutable.ArrayBuffer[Req]] // line -> waiting requests

  private var requests, responses, requestHits, lineHits, primaryMisses, mergedMisses, stallCycles = 0L
  private var outstandingSum, mshrSum = 0L
  private var maxOutstandingSeen = 0

  private def linesOf(addr: Long): Seq[Long] = params.cache match {
    case Some(c) => (addr / c.lineBytes to (addr + recordBytes - 1) / c.lineBytes).map(_ * c.lineBytes)
    case None    => Nil
  }
  private def setOf(line: Long): mutable.ArrayBuffer[Long] = {
    val c = params.cache.get
    sets.get(((line / c.lineBytes) % c.sets).toInt)
  }
  private def present(line: Long): Boolean = setOf(line).contains(line)

  def reqReady(addr: Long): Boolean =
    outstanding.size < params.maxOutstanding && {
      params.cache.isEmpty || {
        val newMisses = linesOf(addr).count(l => !present(l) && !mshrs.contains(l))
        mshrs.size + newMisses <= params.cache.get.mshrs
      }
    }

  def stalled(): Unit = stallCycles += 1

  def accept(addr: Long, tag: Int): Unit = {
    require(reqReady(addr), s"$name: request at address $addr accepted while the port was not ready")
    // readLE fails loudly, naming the address, if the request is outside the image.
    val r = new Req(nextSeq, tag, image.readLE(addr, recordBytes), 0)
    nextSeq += 1
    requests += 1
    outstanding(r.seq) = r
    params.cache match {
      case None => dram.issue(r.seq, recordBytes, now)
      case Some(c) =>
        for (line <- linesOf(addr)) {
          if (present(line)) {
            lineHits += 1
            val s = setOf(line); s -= line; s += line // touch: most recently used
          } else if (mshrs.contains(line)) {
            mergedMisses += 1
            mshrs(line) += r
            r.waitingLines += 1
          } else {
            primaryMisses += 1
            mshrs(line) = mutable.ArrayBuffer(r)
            r.waitingLines += 1
            dram.issue(-1 - line, c.lineBytes, now) // negative IDs name line fills
          }
        }
        if (r.waitingLines == 0) {
          requestHits += 1
          r.readyAt = now + c.hitLatency - 1
          hitPipe.enqueue(r)
        }
    }
  }

  /** The response on offer this cycle: (tag, record data little-endian). */
  def response: Option[(Int, BigInt)] = nextResponse.map(r => (r.tag, r.data))

  private def nextResponse: Option[Req] =
    if (params.inOrder) outstanding.headOption.map(_._2).filter(_.available)
    else ready.headOption

  private def makeAvailable(r: Req): Unit = {
    r.available = true
    if (!params.inOrder) ready.enqueue(r)
  }

  def responseTaken(): Unit = {
    val r = nextResponse.getOrElse(throw new IllegalStateException(s"$name: response taken when none was offered"))
    if (!params.inOrder) ready.dequeue()
    outstanding.remove(r.seq)
    responses += 1
  }

  def tick(): Unit = {
    for (id <- dram.tick(now)) {
      if (id >= 0) makeAvailable(outstanding(id))
      else fill(-1 - id)
    }
    while (hitPipe.nonEmpty && hitPipe.head.readyAt <= now) makeAvailable(hitPipe.dequeue())
    outstandingSum += outstanding.size
    mshrSum += mshrs.size
    maxOutstandingSeen = maxOutstandingSeen.max(outstanding.size)
    now += 1
  }

  private def fill(line: Long): Unit = {
    val c = params.cache.get
    val s = setOf(line)
    if (s.size == c.ways) s.remove(0) // evict the least recently used line
    s += line
    for (r <- mshrs.remove(line).get) {
      r.waitingLines -= 1
      if (r.waitingLines == 0) makeAvailable(r)
    }
  }

  def cycles: Long = now
  def idle: Boolean = outstanding.isEmpty

  def stats: MemStats = MemStats(name, now, requests, responses, dram.bytesMoved, requestHits, lineHits,
    primaryMisses, mergedMisses, stallCycles, outstandingSum, maxOutstandingSeen, mshrSum)
}
