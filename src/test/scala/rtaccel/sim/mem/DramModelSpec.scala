package rtaccel.sim.mem

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.mem.ModelDriver.{drive, drivePorts}
import rtaccel.scene.MemoryImage
import rtaccel.testutil.Seeded

import scala.util.Random

/** What the memory model charges: whole DRAM bursts, one DRAM's bandwidth
  * shared by both ports, latency in ns at the fabric clock, and on-chip
  * memory with none of these. Images are synthetic; triangle requests lie
  * at a 48-byte stride from a 64-byte boundary, so triangle i touches bursts
  * 1, 2, 2, 1 for i mod 4 = 0, 1, 2, 3.
  */
class DramModelSpec extends AnyFlatSpec {
  behavior of "DramModel and the memory kinds"

  private val Tri = SyntheticImage.Tri48
  private def triAt(img: MemoryImage, i: Long): Long = SyntheticImage.tri48(img, i)
  private val Node = MemoryImage.NodeBytes
  private val ddr = MemoryKind.Ddr()
  private def image(seed: Long) = SyntheticImage(nodes = 64, tris = 512, new Random(seed))
  private def fixed(cycles: Int) = MemoryParams(latency = Latency.Fixed(cycles))

  it should "state the ZC706 DDR3: 64-byte bursts, 12.8 GB/s, 64 B/cycle at the 200 MHz MIG clock" in {
    assert(ddr.device.burstBytes == 64 && ddr.device.peakBytesPerSecond == 12.8e9)
    assert(ddr.clock.mhz == 200 && ddr.bytesPerCycle == 64.0)
    assert(MemoryKind.Ddr(FabricClock(250)).bytesPerCycle == 51.2)
  }

  it should "convert ns to whole cycles at the fabric clock, rounding up" in {
    val at200 = FabricClock(200)
    assert(Seq(1, 5, 6, 100, 101, 300).map(at200.cycles) == Seq(1, 1, 2, 20, 21, 60))
    assert(FabricClock(150).cycles(10) == 2 && FabricClock(250).cycles(100) == 25 && FabricClock(166.67).cycles(6) == 2)
    assert(LatencyNs.parse("100").cycles(at200) == Latency.Fixed(20))
    assert(LatencyNs.parse("80-300").cycles(at200) == Latency.Uniform(16, 60))
    for (bad <- Seq("", "0", "-5", "300-80", "1.5", "x", "80-")) {
      val e = intercept[IllegalArgumentException](LatencyNs.parse(bad))
      assert(e.getMessage.contains(s"'$bad'"), s"the error must name the value: ${e.getMessage}")
    }
  }

  it should "charge every burst a record touches: a 48-byte record across a 64-byte boundary costs 128 bytes" in {
    assert(DramModel.burstCharge(0, 48, 64) == 64 && DramModel.burstCharge(48, 48, 64) == 128)
    assert(DramModel.burstCharge(64, 64, 64) == 64 && DramModel.burstCharge(65, 64, 64) == 128 && DramModel.burstCharge(
      0,
      256,
      64
    ) == 256)
    val img = image(1)
    for ((i, bytes, seen) <- Seq((0, 64, 10L), (1, 128, 11L), (2, 128, 11L), (3, 64, 10L))) {
      val m = new MemorySystemModel(img, Tri, fixed(10), "tri")
      val Seq((cycle, _, _)) = drive(m, Seq(triAt(img, i.toLong)))
      // Latency 10, then one cycle of channel per 64-byte burst beyond the first.
      assert(
        m.stats.dramBytes == bytes && cycle == seen,
        s"triangle $i: ${m.stats.dramBytes} bytes, seen at cycle $cycle"
      )
    }
  }

  it should "share one DRAM between the ports: a transfer on one delays the other by its bursts" in {
    val img = image(2)
    def pair() = {
      val b = Backing.privateDdr()
      (
        new MemorySystemModel(img, Node, fixed(10), "node", b),
        new MemorySystemModel(img, Tri, fixed(10), "tri", b),
        b.model
      )
    }
    // Alone, each answers at cycle 10.
    val (n1, t1, d1) = pair()
    val Seq(nr, tr) = drivePorts(Seq(n1, t1), Seq(Seq(img.nodeAddr(0)), Seq(triAt(img, 0))))
    // Both ready in cycle 9: the node (issued first in the cycle) takes that
    // cycle's 64 bytes, the triangle the next.
    assert(nr.map(_._1) == Seq(10L) && tr.map(_._1) == Seq(11L), s"node $nr, triangle $tr")
    assert(d1.stats(n1.cycles).bytes == 128 && n1.stats.dramBytes == 64 && t1.stats.dramBytes == 64)
    // A two-burst triangle issued in cycle 0 holds the channel in cycles 9 and
    // 10; a node issued in cycle 1 (ready in 10) waits until 11, seen at 12.
    val (n2, t2, _) = pair()
    val Seq(nr2, tr2) =
      drivePorts(Seq(n2, t2), Seq(Seq(img.nodeAddr(0)), Seq(triAt(img, 1))), from = Seq(Seq(1L), Seq(0L)))
    assert(tr2.map(_._1) == Seq(11L) && nr2.map(_._1) == Seq(12L), s"node $nr2, triangle $tr2")
    // Private DRAMs would not interfere.
    val Seq(nr3, tr3) = drivePorts(
      Seq(new MemorySystemModel(img, Node, fixed(10), "node"), new MemorySystemModel(img, Tri, fixed(10), "tri")),
      Seq(Seq(img.nodeAddr(0)), Seq(triAt(img, 1))),
      from = Seq(Seq(1L), Seq(0L))
    )
    assert(tr3.map(_._1) == Seq(11L) && nr3.map(_._1) == Seq(11L))
  }

  it should "carry fractional bytes per cycle exactly: 51.2 B/cycle at 250 MHz moves ten bursts in 12.5 cycles" in {
    val img = image(3)
    val m = new MemorySystemModel(img, Node, fixed(1), "node", Backing.privateDdr(MemoryKind.Ddr(FabricClock(250))))
    // Nodes 0, 2, 4, ...: one 64-byte burst each, one request per cycle from cycle 0.
    val rs = drive(m, (0 until 10).map(i => img.nodeAddr(2L * i)))
    assert(rs.last._1 == 13, s"640 bytes at 51.2 B/cycle end in cycle 12, seen in 13; got ${rs.map(_._1)}")
  }

  it should "under random traffic on both ports, never move more than the peak and lose nothing" in Seeded(
    "dram.shared"
  ) { rnd =>
    val img = image(rnd.nextLong())
    val b = Backing.privateDdr()
    val p = MemoryParams(latency = LatencyNs(80, 300).cycles(ddr.clock), maxOutstanding = 16, seed = rnd.nextLong())
    val ms = Seq(
      new MemorySystemModel(img, Node, p, "node", b),
      new MemorySystemModel(img, Tri, p.copy(seed = rnd.nextLong()), "tri", b)
    )
    val addrs =
      Seq(Seq.fill(400)(img.nodeAddr(rnd.nextInt(64).toLong)), Seq.fill(400)(triAt(img, rnd.nextInt(512).toLong)))
    val rs = drivePorts(ms, addrs)
    for (i <- 0 to 1) assert(rs(i).map(_._2).sorted == addrs(i).indices, s"port $i: tags lost or duplicated")
    val charged =
      addrs(0).map(DramModel.burstCharge(_, Node, 64)).sum + addrs(1).map(DramModel.burstCharge(_, Tri, 64)).sum
    val d = b.model.stats(ms.head.cycles)
    assert(d.bytes == charged && ms.map(_.stats.dramBytes).sum == charged, s"charged $charged, dram ${d.toJson}")
    assert(d.busyCycles * 64 >= charged && d.busyShare <= 1.0, s"more than 64 B in a cycle: ${d.toJson}")
    // Every byte crosses the one channel, after at least the shortest latency.
    assert(rs.flatten.map(_._1).max >= charged / 64 + 16, s"finished at ${rs.flatten.map(_._1).max} for $charged bytes")
  }

  it should "serve on-chip memory with a fixed latency and one record per cycle per port, with no DRAM" in {
    val img = image(4)
    val onchip = MemoryParams(latency = Latency.Fixed(MemoryKind.OnChip.LatencyCycles))
    val ms = Seq(
      new MemorySystemModel(img, Node, onchip, "node", Backing.OnChip),
      new MemorySystemModel(img, Tri, onchip, "tri", Backing.OnChip)
    )
    // Straddling triangles included: on chip a record is one read, whatever its alignment.
    val rs =
      drivePorts(ms, Seq((0 until 20).map(i => img.nodeAddr(i.toLong)), (0 until 20).map(i => triAt(img, i.toLong))))
    for (r <- rs) assert(r.map(_._1) == (2L to 21L), s"answers at ${r.map(_._1)}")
    assert(ms.forall(_.stats.dramBytes == 0))
    intercept[IllegalArgumentException](new MemorySystemModel(
      img,
      Tri,
      onchip.copy(cache = Some(CacheParams())),
      "tri",
      Backing.OnChip
    ))
  }
}
