package rtaccel.sim.mem

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
  * cache, a request needs every line its record touches (a record not aligned
  * to its size can straddle two lines): present lines hit, lines already being fetched merge
  * into their MSHR, other lines take a free MSHR and one DRAM line transfer.
  * A request needing more MSHRs than are free is refused until some retire.
  * DRAM transfers (records or line fills) go to `backing`: a DramModel,
  * possibly shared with the other port, that charges whole bursts and
  * shares its bandwidth; or on-chip memory, which answers every request after
  * the port's fixed latency with no bandwidth of its own to share.
  */
final class MemorySystemModel(
    image: MemoryImage,
    val recordBytes: Int,
    params: MemoryParams,
    name: String,
    backing: Backing = Backing.privateDdr()
) {
  backing match {
    case Backing.OnChip =>
      require(params.cache.isEmpty, s"$name: a cache in front of on-chip memory")
      require(
        params.latency.isInstanceOf[Latency.Fixed],
        s"$name: on-chip memory has a fixed latency, got ${params.latency.describe}"
      )
    case _: Backing.Dram => ()
  }
  private val rnd = new Random(params.seed)
  private def drawLatency(): Int = params.latency match {
    case Latency.Fixed(c)        => c
    case Latency.Uniform(lo, hi) => lo + rnd.nextInt(hi - lo + 1)
  }
  private var dramBytes = 0L
  private val client = new DramModel.Client {
    def inOrder: Boolean = params.inOrder
    def completed(id: Long): Unit = if (id >= 0) makeAvailable(outstanding(id)) else fill(-1 - id)
  }
  private def issue(id: Long, addr: Long, n: Int): Unit = backing match {
    case Backing.Dram(d) => dramBytes += d.issue(client, id, addr, n, drawLatency(), now)
    case Backing.OnChip  => throw new IllegalStateException(s"$name: no DRAM behind on-chip memory")
  }

  /** `data` is read once, on acceptance (memory is read-only during a run). */
  private final class Req(val seq: Long, val tag: Int, val data: BigInt, var waitingLines: Int) {
    var readyAt: Long = Long.MaxValue
    var available: Boolean = false
  }
  private var now: Long = 0
  private var nextSeq: Long = 0
  private val outstanding = mutable.LinkedHashMap.empty[Long, Req] // accepted, not yet answered; in seq order
  private val ready = mutable.Queue.empty[Req] // out-of-order mode: available, in order of readiness
  private val hitPipe = mutable.Queue.empty[Req] // cache hits and on-chip reads, ready at readyAt (fixed latency: FIFO)

  // Cache state: per set, line addresses in LRU order (head = least recent).
  private val sets = params.cache.map(c => Array.fill(c.sets)(mutable.ArrayBuffer.empty[Long]))
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
    (backing, params.cache) match {
      case (Backing.OnChip, _) =>
        r.readyAt = now + drawLatency() - 1
        hitPipe.enqueue(r)
      case (_, None) => issue(r.seq, addr, recordBytes)
      case (_, Some(c)) =>
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
            issue(-1 - line, line, c.lineBytes) // negative IDs name line fills
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
    backing match { case Backing.Dram(d) => d.tick(now); case Backing.OnChip => () }
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

  def stats: MemStats = MemStats(
    name,
    now,
    recordBytes,
    requests,
    responses,
    dramBytes,
    requestHits,
    lineHits,
    primaryMisses,
    mergedMisses,
    stallCycles,
    outstandingSum,
    maxOutstandingSeen,
    mshrSum
  )
}

/** The store behind a port's memory system. */
sealed trait Backing
object Backing {

  /** A DRAM channel, private to the port or shared with the other one. */
  final case class Dram(model: DramModel) extends Backing

  /** Block RAM of the port's own: the port's fixed latency, one record per cycle. */
  case object OnChip extends Backing

  def privateDdr(kind: MemoryKind.Ddr = MemoryKind.Ddr()): Dram =
    Dram(new DramModel(kind.bytesPerCycle, kind.device.burstBytes))

  /** The backings of a run's two ports: one shared DRAM, or on-chip memory each. */
  def forPorts(kind: MemoryKind): (Backing, Option[DramModel]) = kind match {
    case d: MemoryKind.Ddr => val b = privateDdr(d); (b, Some(b.model))
    case MemoryKind.OnChip => (OnChip, None)
  }
}
