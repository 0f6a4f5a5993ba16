package rtaccel.study

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.bvh.BvhLayout
import rtaccel.golden.RayRecord
import rtaccel.sim.SyntheticBvh
import rtaccel.testutil.Seeded

/** The DRAM traffic study's accounting (docs/dram-traffic.md): whole lines, the stores' prefixes, the cache's LRU,
  * the treelet schedule's invariants and the ray order. Cheap: no hardware, a few thousand synthetic reads.
  */
class DramTrafficSpec extends AnyFlatSpec {
  behavior of "the DRAM traffic study"

  it should "charge a read the whole 64-byte lines it touches, and nothing for what a store holds" in {
    import MemoryDesign.lineBytes
    assert(lineBytes(64, 48) == 64) // triangle 0 of an array at 64: one line
    assert(lineBytes(112, 48) == 128) // triangle 1: bytes 112..159 straddle two lines
    assert(lineBytes(160, 48) == 128) // triangle 2: 160..207, two lines
    assert(lineBytes(208, 48) == 64) // triangle 3: 208..255, one line (1.5 lines a triangle on average)
    assert(lineBytes(64, 128) == 128) // a 4-wide node
    assert(lineBytes(144, 80) == 128) // an 8q node never touches three lines (80 i + 64 is 16-aligned)
    val img = SyntheticBvh(new scala.util.Random(1), maxDepth = 4, maxLeaf = 3, layout = BvhLayout.Wide(4))
    val store = MemoryDesign(nodeStoreBytes = 2 * img.nodeBytes, triStoreBytes = 3 * 48, tris = TriRecords.Record48)
    assert(MemoryDesign().copy(triStoreBytes = 3 * 64).bytes(img, TriRead(2)) == 0, "the image's 64-byte records")
    assert(MemoryDesign().copy(triStoreBytes = 3 * 64).bytes(img, TriRead(3)) == 64, "one line a record")
    assert(store.bytes(img, NodeRead(1)) == 0 && store.bytes(img, NodeRead(2)) == 128)
    assert(store.bytes(img, TriRead(2)) == 0 && store.bytes(img, TriRead(3)) > 0)
    assert(
      store.bytes(img, LeafRead(0, 2)) == 0,
      "a design that reads triangle by triangle charges the tests, not the leaf"
    )
    val perLeaf = store.copy(tris = TriRecords.Leaf36)
    assert(perLeaf.bytes(img, TriRead(9)) == 0 && perLeaf.bytes(img, LeafRead(1, 3)) == 0 && perLeaf.bytes(
      img,
      LeafRead(1, 4)
    ) > 0)
  }

  it should "count the cores' own block RAM beside the stores, the cache and the queues" in {
    def c(key: String) = Candidates.all.find(_.key == key).get
    // Stores: 228 BRAM36 per MiB (1.5 MiB of nodes, 256 KiB of triangles: 342 + 57), one copy whatever the cores; a
    // 1 MiB cache adds 228 + 9 of tags. Cores: 43.5 BRAM36 each, as make verilog measures the default core.
    assert(Traffic.Cores.map(k => DramTrafficStudy.deviceBram(c("today"), k, 1024, 43.5)) == Seq(443, 486, 573))
    assert(DramTrafficStudy.deviceBram(c("nodes1m"), 2, 1024, 43.5) == 228 + 57 + 87)
    assert(DramTrafficStudy.deviceBram(c("compact-cache"), 2, 1024, 43.5) == 285 + 237 + 87)
    assert(DramTrafficStudy.deviceBram(c("compact-cache"), 2, 1024, 43.5) > MemoryDesign.DeviceBram36)
    assert(DramTrafficStudy.deviceBram(c("compact-cache512k"), 2, 1024, 43.5) == 285 + 119 + 87)
    assert(DramTrafficStudy.deviceBram(c("today"), 2, 1024, 0) == c("today").bram(2, 1024))
  }

  it should "hit a line the cache holds and evict the least recently used line of a full set" in {
    val c = new LineCache(4 * 64) // one set of 4 ways
    assert((0L to 3L).forall(l => !c.access(l)))
    assert(c.access(0)) // LRU order now 1, 2, 3, 0
    assert(!c.access(4)) // evicts 1
    assert(c.access(0) && !c.access(1))
    assert(!new LineCache(0).access(0) && !new LineCache(0).access(0), "no cache: every line is read")
  }

  it should "schedule treelets never costing more than the rays' own reads, and park nobody in one treelet" in Seeded(
    "DramTraffic.treelets"
  ) { rnd =>
    val img = SyntheticBvh(rnd, maxDepth = 6, maxLeaf = 3, layout = BvhLayout.Wide(4))
    val ray = RayRecord(0, Seq(0L, 0L, 0L), Seq(0L, 0L, 0x3f800000L), 0, 0x7f800000L, shadow = false)
    val rays = (0 until 200).map { _ =>
      RayReads(
        ray,
        (0 until 1 + rnd.nextInt(30)).map { _ =>
          if (rnd.nextBoolean()) NodeRead(rnd.nextInt(img.nodeCount.toInt).toLong)
          else TriRead(rnd.nextInt(img.triCount.toInt).toLong)
        }
      )
    }
    val none = MemoryDesign(nodeStoreBytes = 0, triStoreBytes = 0)
    val own = rays.flatMap(_.reads).map(none.bytes(img, _)).sum.toDouble / rays.size
    for (t <- Seq(256L, 1024L, 8192L)) {
      val r = Treelets.run(img, none, rays, t)
      assert(r.bytesPerRay <= own + 1e-9, s"treelets of $t bytes: ${r.bytesPerRay} bytes/ray > the rays' own $own")
      assert(r.treelets >= 1)
    }
    val whole = Treelets.run(img, none, rays, Long.MaxValue / 4)
    assert(whole.treelets == 1 && whole.parksPerRay == 0 && whole.loads <= 1)
    println(f"DramTrafficSpec: seed ${Seeded.seedFor("DramTraffic.treelets")}, ${img.nodeCount} nodes, own $own%.0f bytes/ray, " +
      f"one treelet ${whole.bytesPerRay}%.0f")
  }

  it should "reorder rays by origin cell, then octant, keeping every ray once and ties in order" in {
    def ray(n: Int, x: Float, dx: Float) = RayReads(
      RayRecord(
        n,
        Seq(x, 0f, 0f).map(f => java.lang.Float.floatToRawIntBits(f).toLong & 0xffffffffL),
        Seq(dx, 1f, 1f).map(f => java.lang.Float.floatToRawIntBits(f).toLong & 0xffffffffL),
        0,
        0x7f800000L,
        shadow = false
      ),
      Vector.empty
    )
    val rays = Vector(ray(0, 0f, -1f), ray(1, 10f, 1f), ray(2, 0f, 1f), ray(3, 10f, 1f), ray(4, 0f, -1f))
    val order = RayOrder.sorted(rays).map(_.ray.number)
    assert(order == Vector(2, 0, 4, 1, 3), s"got $order")
  }
}
