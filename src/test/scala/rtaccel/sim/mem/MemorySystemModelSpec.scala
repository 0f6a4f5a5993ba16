package rtaccel.sim.mem

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.scene.MemoryImage
import rtaccel.sim.mem.ModelDriver.drive
import rtaccel.testutil.Seeded

import scala.util.Random

/** The memory model is itself test equipment, so it is tested first: timing,
  * bandwidth, ordering, limits, cache behaviour and the bytes it returns.
  * (Bursts, the shared DRAM and on-chip memory: `DramModelSpec`.) By default a
  * port has a DRAM of its own: the ZC706's DDR3 at 200 MHz, 64 B per cycle.
  */
class MemorySystemModelSpec extends AnyFlatSpec {
  behavior of "MemorySystemModel"

  private val Tri = SyntheticImage.Tri48
  private def triAt(img: MemoryImage, i: Long): Long = SyntheticImage.tri48(img, i)

  private def image(rnd: Random) = SyntheticImage(nodes = 64, tris = 512, rnd)

  it should "answer an uncontended request exactly `latency` cycles after it was accepted" in {
    for (l <- Seq(1, 2, 10, 100)) {
      val img = image(new Random(1))
      val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(l)), "tri")
      val Seq((cycle, tag, _)) = drive(m, Seq(triAt(img, 3))) // bytes [144, 192) of its section: one burst
      assert(cycle == l && tag == 0, s"latency $l: answered at cycle $cycle")
    }
  }

  it should "return each record's bytes, little-endian, as they stand in the image" in Seeded("mem.data") { rnd =>
    val img = image(rnd)
    val idx = Seq.fill(300)(rnd.nextInt(512).toLong)
    val m =
      new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Uniform(1, 40), seed = rnd.nextLong()), "tri")
    for ((_, tag, data) <- drive(m, idx.map(i => triAt(img, i.toLong)))) {
      val base = triAt(img, idx(tag)).toInt
      val expected = (0 until Tri).map(i => BigInt(img.bytes(base + i) & 0xff) << (8 * i)).sum
      assert(data == expected, s"request $tag (triangle ${idx(tag)}): wrong bytes")
    }
  }

  it should "limit throughput to its bandwidth, charging whole bursts" in {
    val img = image(new Random(2))
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(1)), "tri")
    val rs = drive(m, (0 until 100).map(i => triAt(img, i.toLong)))
    // Consecutive 48-byte records from a 64-byte boundary touch 1, 2, 2, 1
    // bursts in turn: 150 bursts of 64 bytes for 100 records, one burst per
    // cycle, so the channel (not the one request per cycle) sets the pace.
    assert(m.stats.dramBytes == 150 * 64, m.stats.toJson)
    assert(rs.last._1 >= 150 && rs.last._1 <= 152, s"last response at cycle ${rs.last._1}")
  }

  it should "keep request order when in-order, and reorder when not, losing nothing" in Seeded("mem.order") { rnd =>
    val img = image(rnd)
    val addrs = Seq.fill(500)(triAt(img, rnd.nextInt(512).toLong))
    for (inOrder <- Seq(true, false)) {
      val p =
        MemoryParams(latency = Latency.Uniform(50, 300), inOrder = inOrder, maxOutstanding = 32, seed = rnd.nextLong())
      val tags = drive(new MemorySystemModel(img, Tri, p, "tri"), addrs).map(_._2)
      assert(tags.sorted == addrs.indices, s"inOrder=$inOrder: tags lost or duplicated")
      val inversions = tags.zip(tags.tail).count { case (a, b) => a > b }
      if (inOrder) assert(inversions == 0) else assert(inversions > 0, "random latencies produced no reordering")
    }
  }

  it should "never hold more than maxOutstanding requests" in {
    val img = image(new Random(3))
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(100), maxOutstanding = 4), "tri")
    drive(m, (0 until 40).map(i => triAt(img, i.toLong)))
    assert(m.stats.maxOutstanding == 4)
    assert(m.stats.stallCycles > 0)
  }

  it should "be deterministic for a seed" in {
    val img = image(new Random(4))
    val addrs = (0 until 200).map(i => triAt(img, (i * 7 % 512).toLong))
    def once() =
      drive(new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Uniform(10, 90), seed = 42), "tri"), addrs)
    assert(once() == once())
  }

  behavior of "MemorySystemModel with a non-blocking cache"

  private val cache = CacheParams(lineBytes = 64, capacityBytes = 1024, ways = 2, mshrs = 4, hitLatency = 2)

  it should "merge misses to a line under fetch into one DRAM transfer, then hit" in {
    val img = image(new Random(5))
    val m = new MemorySystemModel(
      img,
      MemoryImage.NodeBytes,
      MemoryParams(latency = Latency.Fixed(50), cache = Some(cache)),
      "node"
    )
    val a = img.nodeOffset // nodes 0 and 1 share the first 64-byte line
    val rs = drive(m, Seq(a, a + 32, a))
    val s = m.stats
    assert(s.primaryMisses == 1 && s.mergedMisses == 2 && s.dramBytes == 64, s.toJson)
    // The fill is ready after 50 cycles and crosses the 64 B/cycle channel in
    // one (visible from cycle 50); the port then answers one per cycle.
    assert(rs.map(_._1) == Seq(50L, 51L, 52L), s"all three wait for the one fill: ${rs.map(_._1)}")
    val again = drive(m, Seq(a + 32))
    assert(again.head._1 == m.cycles - 1 && m.stats.requestHits == 1, s"hit after fill: ${m.stats.toJson}")
  }

  it should "evict the least recently used line of a full set" in {
    val img = image(new Random(6))
    val m = new MemorySystemModel(
      img,
      MemoryImage.NodeBytes,
      MemoryParams(latency = Latency.Fixed(5), cache = Some(cache)),
      "node"
    )
    val setStride = cache.sets * cache.lineBytes // addresses this far apart share a set
    val base = img.nodeOffset
    drive(m, Seq(base, base + setStride, base + 2 * setStride)) // 3 lines into a 2-way set
    drive(m, Seq(base + 2 * setStride, base + setStride)) // both still present
    assert(m.stats.requestHits == 2, m.stats.toJson)
    drive(m, Seq(base)) // was evicted first
    assert(m.stats.primaryMisses == 4, m.stats.toJson)
  }

  it should "refuse a request that needs more MSHRs than are free" in {
    val img = image(new Random(7))
    val one = cache.copy(mshrs = 1)
    val m = new MemorySystemModel(img, Tri, MemoryParams(latency = Latency.Fixed(20), cache = Some(one)), "tri")
    // Triangle 1 spans bytes [48, 96) of its section: two lines, so it can never
    // start with one MSHR unless one of its lines is present.
    val first = triAt(img, 0)
    assert(m.reqReady(first))
    m.accept(first, 0)
    assert(!m.reqReady(triAt(img, 10)), "a second miss must wait for the only MSHR")
  }
}
