package rtaccel.mem

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.scene.MemoryImage
import rtaccel.testutil.Seeded

import scala.collection.mutable
import scala.util.Random

/** The memory model is itself test equipment, so it is tested first: timing,
  * bandwidth, ordering, limits, cache behaviour and the bytes it returns.
  */
class MemorySystemModelSpec extends AnyFlatSpec {
  behavior of "MemorySystemModel"

  private val Tri = MemoryImage.TriBytes

  /** Drives a model like a DUT would: issues `addrs` as fast as accepted,
    * always ready for responses. Returns (cycle seen, tag, data) per response.
    */
  private def run(m: MemorySystemModel, addrs: Seq[Long], maxCycles: Int = 100000): Seq[(Long, Int, BigInt)] = {
    val out = mutable.ArrayBuffer.empty[(Long, Int, BigInt)]
    var next = 0
    while ((next < addrs.size || !m.idle) && m.cycles < maxCycles) {
      if (next < addrs.size) {
        if (m.reqReady(addrs(next))) { m.accept(addrs(next), next); next += 1 }
        else m.stalled()
      }
      m.response.foreach { case (tag, data) => out += ((m.cycles, tag, data)); m.responseTaken() }
      m.tick()
    }
    assert(next == addrs.size && m.idle, s"model did not drain within $maxCycles cycles")
    out.toSeq
  }

  private def image(rnd: Random) = SyntheticImage(nodes = 64, tris = 512, rnd)

  it should "answer an uncontended request exactly `latency` cycles after it was accepted" in {
    for (l <- Seq(1, 2, 10, 100)) {
      val img = image(new Random(1))
      val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(l), bytesPerCycle = 64), "tri")
      val Seq((cycle, tag, _)) = run(m, Seq(img.triAddr(3)))
      assert(cycle == l && tag == 0, s"latency $l: answered at cycle $cycle")
    }
  }

  it should "return each record's bytes, little-endian, as they stand in the image" in Seeded("mem.data") { rnd =>
    val img = image(rnd)
    val idx = Seq.fill(300)(rnd.nextInt(512).toLong)
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Uniform(1, 40), seed = rnd.nextLong()), "tri")
    for ((_, tag, data) <- run(m, idx.map(img.triAddr))) {
      val base = img.triAddr(idx(tag)).toInt
      val expected = (0 until Tri).map(i => BigInt(img.bytes(base + i) & 0xff) << (8 * i)).sum
      assert(data == expected, s"request $tag (triangle ${idx(tag)}): wrong bytes")
    }
  }

  it should "limit throughput to its bandwidth" in {
    val img = image(new Random(2))
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(1), bytesPerCycle = 16), "tri")
    val rs = run(m, (0 until 100).map(i => img.triAddr(i.toLong)))
    // 48 bytes at 16 bytes/cycle: one record every 3 cycles once the channel is busy.
    assert(rs.last._1 >= 300 && rs.last._1 <= 303, s"last response at cycle ${rs.last._1}")
    assert(m.stats.dramBytes == 100 * Tri)
  }

  it should "keep request order when in-order, and reorder when not, losing nothing" in Seeded("mem.order") { rnd =>
    val img = image(rnd)
    val addrs = Seq.fill(500)(img.triAddr(rnd.nextInt(512).toLong))
    for (inOrder <- Seq(true, false)) {
      val p = MemoryParams(latency = Latency.Uniform(50, 300), inOrder = inOrder, maxOutstanding = 32, seed = rnd.nextLong())
      val tags = run(new MemorySystemModel(img, Tri, p, "tri"), addrs).map(_._2)
      assert(tags.sorted == addrs.indices, s"inOrder=$inOrder: tags lost or duplicated")
      val inversions = tags.zip(tags.tail).count { case (a, b) => a > b }
      if (inOrder) assert(inversions == 0) else assert(inversions > 0, "random latencies produced no reordering")
    }
  }

  it should "never hold more than maxOutstanding requests" in {
    val img = image(new Random(3))
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(100), maxOutstanding = 4), "tri")
    run(m, (0 until 40).map(i => img.triAddr(i.toLong)))
    assert(m.stats.maxOutstanding == 4)
    assert(m.stats.stallCycles > 0)
  }

  it should "be deterministic for a seed" in {
    val img = image(new Random(4))
    val addrs = (0 until 200).map(i => img.triAddr((i * 7 % 512).toLong))
    def once() = run(new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Uniform(10, 90), seed = 42), "tri"), addrs)
    assert(once() == once())
  }

  behavior of "MemorySystemModel with a non-blocking cache"

  private val cache = CacheParams(lineBytes = 64, capacityBytes = 1024, ways = 2, mshrs = 4, hitLatency = 2)

  it should "merge misses to a line under fetch into one DRAM transfer, then hit" in {
    val img = image(new Random(5))
    val m = new MemorySystemModel(img, MemoryImage.NodeBytes, MemoryParams(latency = Latency.Fixed(50), cache = Some(cache)), "node")
    val a = img.nodeOffset // nodes 0 and 1 share the first 64-byte line
    val rs = run(m, Seq(a, a + 32, a))
    val s = m.stats
    assert(s.primaryMisses == 1 && s.mergedMisses == 2 && s.dramBytes == 64, s.toJson)
    // The fill is ready after 50 cycles and crosses the 16 B/cycle channel in
    // 4 more (visible from cycle 50 + 4 - 1 = 53); the port then answers one per cycle.
    assert(rs.map(_._1) == Seq(53L, 54L, 55L), s"all three wait for the one fill: ${rs.map(_._1)}")
    val again = run(m, Seq(a + 32))
    assert(again.head._1 == m.cycles - 1 && m.stats.requestHits == 1, s"hit after fill: ${m.stats.toJson}")
  }

  it should "evict the least recently used line of a full set" in {
    val img = image(new Random(6))
    val m = new MemorySystemModel(img, MemoryImage.NodeBytes, MemoryParams(latency = Latency.Fixed(5), cache = Some(cache)), "node")
    val setStride = cache.sets * cache.lineBytes // addresses this far apart share a set
    val base = img.nodeOffset
    run(m, Seq(base, base + setStride, base + 2 * setStride)) // 3 lines into a 2-way set
    run(m, Seq(base + 2 * setStride, base + setStride))         // both still present
    assert(m.stats.requestHits == 2, m.stats.toJson)
    run(m, Seq(base))                                           // was evicted first
    assert(m.stats.primaryMisses == 4, m.stats.toJson)
  }

  it should "refuse a request that needs more MSHRs than are free" in {
    val img = image(new Random(7))
    val one = cache.copy(mshrs = 1)
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(20), cache = Some(one)), "tri")
    // Triangle 1 spans bytes [48, 96) of its section: two lines, so it can never
    // start with one MSHR unless one of its lines is present.
    val first = img.triAddr(0)
    assert(m.reqReady(first))
    m.accept(first, 0)
    assert(!m.reqReady(img.triAddr(10)), "a second miss must wait for the only MSHR")
  }
}
