package rtaccel.system

import chisel3._
import chiseltest._

import scala.collection.mutable
import scala.util.Random
import rtaccel.sim.axi.{AxiMemoryHarness, AxiMemoryModel, AxiMemoryParams, SparseMemory}

/** Drives a MemoryFabric (MemoryFabricSpec's configuration) against an
  * AxiMemoryModel in a single-threaded loop, with a scoreboard per client:
  * each response must answer an outstanding request of its client (by tag),
  * exactly once, with the bytes memory holds.
  */
final class FabricEnv(dut: MemoryFabric, rnd: Random, params: AxiMemoryParams) {
  import MemoryFabricSpec._

  /** The slave's beat is the fabric's m_axi width (MemoryFabricSpec.sys). */
  val mem = new AxiMemoryHarness(dut.io.axi, new AxiMemoryModel(params.copy(beatBytes = sys.axiDataBytes)))
  private val image = Array.fill(ReadSpan)(rnd.nextInt(256).toByte)
  mem.model.mem.write(0, image)
  private def expected(addr: Long, n: Int): BigInt = SparseMemory.toLE(image.slice(addr.toInt, addr.toInt + n))

  private final case class Pending(addr: Long, data: BigInt, cycle: Long)
  private val outstanding = readers.map(_ => mutable.HashMap.empty[Int, Pending])
  private val written = mutable.HashMap.empty[Long, BigInt] // 32-byte record address -> data
  /** A line write offered: 64-byte aligned address, the line's 64 bytes, which of its two 32-byte records to write. */
  private type Line = (Long, BigInt, Int)
  var cycle = 0L
  var nodeRequests, otherRequests, storeRequests, straddles, writesSent, linesSent = 0L

  /** Triangle-client reads, and those the triangle store was loaded to serve. */
  var triRequests, triStoreRequests = 0L

  /** The triangle store's `done` one and two cycles ago: it serves only once `done` has held two cycles (its
    * limit registers settle), so a read in the first two cycles after the load goes to DRAM. */
  private var triDoneAgo = (false, false)

  for (r <- dut.io.readers) { r.req.valid.poke(false.B); r.resp.ready.poke(false.B) }
  dut.io.write.valid.poke(false.B)
  dut.io.store.start.poke(false.B)
  dut.io.triStore.start.poke(false.B)

  private def fail(msg: String): Nothing = throw new AssertionError(s"cycle $cycle: $msg")

  /** One cycle: `offer(c)` is client c's request (address, tag) if it drives one; `ready(c)` its resp.ready. */
  private def cycleWith(
      offer: Int => Option[(Long, Int)],
      ready: Int => Boolean,
      write: Option[Line] = None,
      onResp: (Int, Pending) => Unit = (_, _) => ()
  ): Unit = {
    val storeDone = dut.io.store.done.peek().litToBoolean
    val stored = dut.io.store.storedBytes.peek().litValue.toLong
    val triDoneNow = dut.io.triStore.done.peek().litToBoolean
    val triDone = triDoneNow && triDoneAgo._2
    triDoneAgo = (triDoneNow, triDoneAgo._1)
    val triStored = dut.io.triStore.storedBytes.peek().litValue.toLong
    val offers = readers.indices.map(offer)
    for ((r, c) <- dut.io.readers.zipWithIndex) {
      offers(c) match {
        case Some((addr, tag)) => r.req.valid.poke(true.B); r.req.bits.addr.poke(addr.U); r.req.bits.tag.poke(tag.U)
        case None              => r.req.valid.poke(false.B)
      }
      r.resp.ready.poke(ready(c).B)
    }
    write match {
      case Some((a, d, h)) =>
        dut.io.write.valid.poke(true.B); dut.io.write.bits.addr.poke(a.U); dut.io.write.bits.data.poke(d.U)
        dut.io.write.bits.halves.poke(h.U)
      case None => dut.io.write.valid.poke(false.B)
    }
    mem.drive()
    for ((r, c) <- dut.io.readers.zipWithIndex) {
      if (r.resp.valid.peek().litToBoolean && ready(c)) {
        val tag = r.resp.bits.tag.peek().litValue.toInt
        val data = r.resp.bits.data.peek().litValue
        val p = outstanding(c).remove(tag).getOrElse(
          fail(s"client $c: response with tag $tag, which has no request outstanding")
        )
        if (data != p.data)
          fail(
            s"client $c tag $tag: ${readers(c).recordBytes} bytes at 0x${p.addr.toHexString}: got ${data.toString(16)}, expected ${p.data.toString(16)}"
          )
        onResp(c, p)
      }
      offers(c).foreach { case (addr, tag) =>
        if (r.req.ready.peek().litToBoolean) {
          val n = readers(c).recordBytes
          outstanding(c)(tag) = Pending(addr, expected(addr, n), cycle)
          if (addr / 4096 != (addr + n - 1) / 4096) straddles += 1
          if (nodeFlags(c)) {
            nodeRequests += 1
            if (storeDone && addr >= NodeBase && addr < NodeBase + stored && (addr - NodeBase) % n == 0)
              storeRequests += 1
          } else if (triFlags(c)) {
            triRequests += 1
            // Served on chip: the whole record stored, 16-byte aligned in the array (TriStore).
            if (triDone && addr >= TriBase && addr + n <= TriBase + triStored && (addr - TriBase) % 16 == 0)
              triStoreRequests += 1
          } else otherRequests += 1
        }
      }
    }
    // writesSent counts records (writesDone counts the records of acknowledged writes).
    write.foreach { case (a, d, h) =>
      if (dut.io.write.ready.peek().litToBoolean) { linesSent += 1 }
      if (dut.io.write.ready.peek().litToBoolean) for (k <- 0 until 2 if (h >> k & 1) == 1) {
        written(a + 32 * k) = (d >> (256 * k)) & ((BigInt(1) << 256) - 1); writesSent += 1
      }
    }
    dut.clock.step()
    mem.tick()
    cycle += 1
    if (cycle > 400000) fail("no progress: over 400,000 cycles")
  }

  private def freeTag(c: Int): Option[Int] = {
    val free = (0 until (1 << readers(c).tagBits)).filterNot(outstanding(c).contains)
    if (free.isEmpty) None else Some(free(rnd.nextInt(free.size)))
  }

  private def randomAddr(c: Int): Long = {
    val n = readers(c).recordBytes
    if (nodeFlags(c)) NodeBase + NodeBytes.toLong * rnd.nextInt(NodeCount)
    // A tenth of the triangle clients' reads at any byte of the array's start: 16-byte aligned ones may hit, the rest go to DRAM.
    else if (triFlags(c) && rnd.nextDouble() < 0.1) TriBase + rnd.nextInt(4096)
    else if (n == 48) TriBase + 48L * rnd.nextInt(120)
    else if (rnd.nextDouble() < 0.3) 4096L * (1 + rnd.nextInt(ReadSpan / 4096 - 1)) - 1 - rnd.nextInt(n - 1)
    else rnd.nextInt(ReadSpan - n).toLong
  }

  /** Pulses store.start (triStore.start with `tri`); the load proceeds while other traffic runs. */
  def startLoad(base: Long, bytes: Int, tri: Boolean = false): Unit = {
    val l = if (tri) dut.io.triStore else dut.io.store
    l.base.poke(base.U)
    l.bytes.poke(bytes.U)
    l.start.poke(true.B)
    cycleWith(_ => None, _ => true)
    l.start.poke(false.B)
  }

  /** Loads the node store and waits for `done`. */
  def loadStore(base: Long, bytes: Int): Unit = {
    startLoad(base, bytes)
    while (!dut.io.store.done.peek().litToBoolean) cycleWith(_ => None, _ => true)
  }

  /** Random reads from every client and random writes, until all are answered; then checks the writes in memory. */
  def run(requestsPerClient: Int, writes: Int): Unit = {
    val left = Array.fill(readers.size)(requestsPerClient)
    var writesLeft = writes
    var offer: Option[Line] = None
    while (left.exists(_ > 0) || outstanding.exists(_.nonEmpty) || linesSent < writes) {
      val offers = readers.indices.map { c =>
        if (left(c) > 0 && rnd.nextDouble() < 0.6) freeTag(c).map(t => (randomAddr(c), t)) else None
      }
      if (offer.isEmpty && writesLeft > 0 && rnd.nextDouble() < 0.5) {
        offer = Some((WriteBase + 64L * rnd.nextInt(WriteSpan / 64), BigInt(512, rnd), 1 + rnd.nextInt(3)))
        writesLeft -= 1
      }
      val readies = readers.indices.map(_ => rnd.nextDouble() < 0.7)
      val sentBefore = linesSent
      cycleWith(offers, readies, offer)
      if (linesSent > sentBefore) offer = None
      for (
        c <- readers.indices
        if offers(c).exists { case (a, t) => outstanding(c).get(t).exists(p => p.addr == a && p.cycle == cycle - 1) }
      )
        left(c) -= 1
    }
    // All B responses in, then every written record must be in memory.
    while (dut.io.writesDone.peek().litValue < writesSent) cycleWith(_ => None, _ => true)
    for ((a, d) <- written) {
      val got = mem.model.mem.readLE(a, 32)
      if (got != d) fail(s"write at 0x${a.toHexString}: memory holds ${got.toString(16)}, expected ${d.toString(16)}")
    }
    if (!mem.model.idle) fail("the slave still holds bursts after every request was answered")
  }

  /** `cycles` cycles with no requests, every client ready: a response now would answer nothing. */
  def quiet(cycles: Int): Unit = for (_ <- 0 until cycles) cycleWith(_ => None, _ => true)

  /** Reads records 0 .. records-1 (`stride` bytes apart from `base`), clients `pair` in turn, always ready; returns
    * each read's latency. */
  def storeOnly(records: Int, pair: (Int, Int) = (0, 1), base: Long = NodeBase, stride: Int = NodeBytes): Seq[Long] = {
    val lat = mutable.ArrayBuffer.empty[Long]
    var next = 0
    while (next < records || outstanding.exists(_.nonEmpty)) {
      val c = if (next % 2 == 0) pair._1 else pair._2
      val o = Option.when(next < records)((base + stride.toLong * next, next % (1 << readers(c).tagBits)))
      // Taken when its tag is outstanding afterwards (it was not before): a
      // count would miss it when an earlier answer of the same client leaves
      // in the same cycle (store latency 2, the client asking every other cycle).
      require(
        o.forall(x => !outstanding(c).contains(x._2)),
        s"storeOnly: tag ${o.map(_._2)} of client $c is still outstanding"
      )
      cycleWith(i => if (i == c) o else None, _ => true, onResp = (_, p) => lat += cycle - p.cycle)
      if (o.exists(x => outstanding(c).contains(x._2))) next += 1
    }
    lat.toSeq
  }

  /** One read by `client` at `addr`, waited for. */
  def readOne(client: Int, addr: Long): Unit = {
    var sent = false
    while (!sent || outstanding(client).nonEmpty) {
      val before = outstanding(client).size
      cycleWith(c => Option.when(c == client && !sent)((addr, 0)), _ => true)
      if (outstanding(client).size > before) sent = true
    }
  }
}
