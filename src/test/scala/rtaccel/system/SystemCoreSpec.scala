package rtaccel.system

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.golden.{ArithGolden, RayRecord, TraversalGolden}
import rtaccel.regress.Bridge
import rtaccel.scene.{MemoryImage, ScenePackage}
import rtaccel.testutil.{Seeded, SlowTest}
import rtaccel.{AccelConfig, Datapath, ErrorFlags}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{Backends, ControlWorkload, FieldDatapath, SystemHarness, SystemSimTop}
import rtaccel.sim.axi.AxiMemoryParams
import rtaccel.sim.mem.LatencyNs

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.Paths
import scala.util.Random

/** SystemCore (the system top in bundle form, as SystemSimTop wraps it) through
  * its ports only: registers over AXI4-Lite, scene,
  * rays and hits in an AXI4 slave memory model (random latency, back-pressure,
  * reordering across IDs, protocol checks). Every ray's hit record is compared
  * with the golden model, and the counters with the hits.
  */
class SystemCoreSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "SystemCore"

  private val fieldCfg = AccelConfig(
    numRayIds = 8,
    stackDepth = 12,
    maxNodes = 1 << 10,
    maxTriangles = 1 << 10,
    maxLeafSize = 4,
    layout = BvhLayout.Wide(4)
  )

  /** Runs one batch of `rays` (renumbered 0..n-1; ray i gets reserved flag bits `flags(i)`) and checks every hit record. */
  private def batch[T <: chisel3.Data, S](
      h: SystemHarness[T],
      cfg: AccelConfig,
      img: MemoryImage,
      golden: ArithGolden[S],
      rays: IndexedSeq[RayRecord],
      lay: SystemHarness.Layout,
      flags: Int => Int,
      what: String
  ): Long = {
    val rs = rays.zipWithIndex.map { case (r, i) => r.copy(number = i.toLong) }
    h.putRays(lay.rayBase, rs, flags)
    h.mem.write(lay.hitBase, Array.fill(SystemConfig.HitBytes * rs.size)(0xa5.toByte))
    h.write("CTRL", 1L << RegisterMap.field("CTRL", "CLEAR_COUNTERS").lsb)
    val (beats0, wbeats0) = (h.model.readBeats, h.model.writeBeats)
    val cycles = h.runBatch(lay.rayBase, rs.size, lay.hitBase, limit = 2000000)
    val traces = rs.zipWithIndex.map { case (r, i) =>
      // A reserved flag bit makes the ray invalid: the hardware sets its origin x to a quiet NaN (RayDma).
      val asSeen = if ((flags(i) & ~1) != 0) r.copy(origin = r.origin.updated(0, RayDma.QuietNaN)) else r
      TraversalGolden.trace(cfg, img, golden, asSeen)
    }
    val hits = rs.indices.map { i =>
      val (hw, reserved) = h.hitRecord(lay.hitBase, i)
      val e = traces(i).hit
      assert(
        hw.number == i && reserved == 0,
        s"$what: hit record $i: number ${hw.number}, reserved bits 0x${reserved.toHexString} (unwritten records read 0xa5a5a5a5)"
      )
      assert(
        TraversalGolden.agrees(rs(i), hw, e),
        s"$what: ray $i (shadow=${rs(i).shadow}): hardware $hw, golden $e (errors ${ErrorFlags.describe(hw.errors)})"
      )
      hw
    }
    val n = rs.size
    assert(h.read("RAYS_DONE") == n, s"$what: RAYS_DONE")
    for ((b, name) <- RegisterMap.errorFlags)
      assert(h.read(s"ERR_COUNT_$name") == hits.count(x => ((x.errors >> b) & 1) == 1), s"$what: ERR_COUNT_$name")
    assert(h.read64("RAYS_IN") == n && h.read64("HITS_OUT") == n, s"$what: RAYS_IN/HITS_OUT")
    assert(h.read64("AXI_READ_BEATS") == h.model.readBeats - beats0, s"$what: AXI_READ_BEATS vs the memory's count")
    assert(h.read64("AXI_WRITE_BEATS") == h.model.writeBeats - wbeats0, s"$what: AXI_WRITE_BEATS vs the memory's count")
    // The cores' node reads are the fabric's node-store hits and misses (two independent counts).
    assert(
      h.read64("NODE_FETCHES") == h.read64("NODE_STORE_HITS") + h.read64("NODE_STORE_MISSES"),
      s"$what: NODE_FETCHES vs the node store's hits + misses"
    )
    // The golden walk's tests are a lower bound: the hardware may test a triangle before a closer hit's tmax reaches it.
    assert(
      h.read64("TRI_TESTS") >= traces.map(_.triTests).sum && h.read64("BOX_TESTS") >= traces.map(_.boxTests).sum,
      s"$what: TRI_TESTS/BOX_TESTS below the golden walk's"
    )
    val c = h.read64("CYCLES").toLong
    assert(c > 0 && c <= cycles, s"$what: CYCLES $c, driver saw $cycles")
    assert(!h.status("BROKEN") && !h.status("AXI_ERROR"), s"$what: STATUS BROKEN/AXI_ERROR")
    println(f"$what: $n rays in $c%,d cycles (${n.toDouble / c}%.4f rays/cycle), ${hits.count(_.hit)} hits")
    c
  }

  private def withHeader(img: MemoryImage, word: Int, value: Long): Array[Byte] = {
    val b = img.bytes.clone()
    ByteBuffer.wrap(b).order(ByteOrder.LITTLE_ENDIAN).putInt(4 * word, value.toInt)
    b
  }

  it should "run the driver sequence on a synthetic scene with 3 cores (sharing the stores' two ports): registers, hits, " +
    "counters, two batches, scene errors" in
    Seeded("RtAccelSystem.field2") { rnd =>
      val (img, _) = ControlWorkload.treeOf(BvhLayout.Wide(4), rnd)
      val cfg = fieldCfg.copy(stackDepth = img.bvhDepth.toInt.max(1))
      val sys = SystemConfig(core = cfg, cores = 3)
      val rays = ControlWorkload.makeRays(rnd, 160)
      val lay = SystemHarness.layout(img, rays.size, skew = 60) // ray and hit buffers cross 4 KB pages
      test(new SystemSimTop(sys, FieldDatapath)).withAnnotations(Backends.verilator) { dut =>
        val h = new SystemHarness(dut, AxiMemoryParams().harsh(rnd.nextLong()))
        h.put(lay.sceneBase, img.bytes)
        // Identity, configuration, access rules.
        assert(h.read("ID") == RegisterMap.Id && h.read("VERSION") == RegisterMap.Version)
        assert(h.read("CONFIG_CORES") == 3 && h.read("CONFIG_LAYOUT") == 4 && h.read("CONFIG_RAY_IDS") == 8)
        assert(h.read("CONFIG_STACK_DEPTH") == cfg.stackDepth && h.read("CONFIG_FLOAT") == (8 << 8 | 23) && h.read(
          "CONFIG_AXI_DATA_BITS"
        ) == sys.axiDataBits)
        assert(h.readResp(0xffc)._2 == 2 && h.write(0xffc, 1) == 2, "unmapped address: SLVERR")
        assert(
          h.write(RegisterMap("ID").offset, 0) == 0 && h.read("ID") == RegisterMap.Id,
          "a write to ro is ignored (OKAY)"
        )
        h.write("RAY_BASE", 0x11223344L)
        assert(
          h.write(RegisterMap("RAY_BASE").offset, 0xaabbccddL, strb = 0x2) == 0 && h.read("RAY_BASE") == 0x1122cc44L,
          "wstrb"
        )
        assert(h.read("CTRL") == 0, "CTRL reads 0")
        h.write("RAY_COUNT", 4); h.write("HIT_BASE", lay.hitBase)
        h.write("CTRL", 1) // START without a scene: ignored
        for (_ <- 0 until 20) h.step()
        assert(
          !h.status("BUSY") && !h.status("DONE") && h.read("IRQ_STATUS") == 0,
          "START without SCENE_READY is ignored"
        )

        assert(h.loadScene(lay.sceneBase) == 0 && h.status("SCENE_READY") && !h.status("SCENE_ERROR"), "good scene")
        // Every 17th ray has a reserved flag bit set.
        batch(
          h,
          cfg,
          img,
          FieldDatapath.Golden,
          rays,
          lay,
          i => if (i % 17 == 5) 1 << (1 + i % 31) else 0,
          "synthetic, 3 cores"
        )
        // A second batch from another ray buffer: per-batch counts start again.
        val lay2 = lay.copy(rayBase = lay.rayBase + 64 * 7)
        batch(
          h,
          cfg,
          img,
          FieldDatapath.Golden,
          ControlWorkload.makeRays(rnd, 37),
          lay2,
          _ => 0,
          "synthetic, second batch"
        )
        // 64-bit counters: reading _LO latches _HI.
        assert(h.read64("CYCLES") == h.read64("CYCLES"))

        // Scene errors: each corruption of the header, and a misaligned base.
        val bad = lay.hitBase + 0x8000
        for (
          (bytes, base, code) <- Seq(
            (withHeader(img, 0, 0x12345678), bad, 1),
            (withHeader(img, 2, MemoryImage.Version - 1), bad, 2),
            (withHeader(img, 11, 2), bad, 3),
            (withHeader(img, 7, 64), bad, 4),
            (withHeader(img, 8, 32), bad, 4),
            (img.bytes, bad + 4, 5),
            (withHeader(img, 6, img.triOffset + 8), bad, 5),
            (withHeader(img, 10, cfg.stackDepth + 1), bad, 6)
          )
        ) {
          h.put(base, bytes)
          assert(h.loadScene(base) == code, s"scene error code for case $code")
          assert(h.status("SCENE_ERROR") && !h.status("SCENE_READY"), s"STATUS after scene error $code")
          val done = h.read("RAYS_DONE")
          h.write("CTRL", 1)
          for (_ <- 0 until 10) h.step()
          assert(!h.status("BUSY") && h.read("RAYS_DONE") == done, "START after a failed load is ignored")
        }
        assert(h.loadScene(lay.sceneBase) == 0 && h.status("SCENE_READY"), "the good scene loads again")
      }
    }

  private val bridge = Paths.get("nori-bridge/target/release/nori-bridge")

  // A whole-system build (about a minute), so `make test-slow`, not `make test`: there the same system top traces
  // the Cornell box's camera rays with one core, every hit against the golden model, in `make cppsim-test` (the
  // C++ AXI/DDR model) and `make test-cocotb` (cocotbext-axi's models, back-pressure on every channel).
  it should "match the golden model in FP32 on the Cornell box (4-wide nodes, 1 core, DDR latency)" taggedAs SlowTest in Seeded(
    "RtAccelSystem.cornell"
  ) { rnd =>
    require(java.nio.file.Files.isExecutable(bridge), s"$bridge is missing: run `make setup` (it builds nori-bridge)")
    val dir = Paths.get("build/test-scenes/cornell-box-primary-bvh4")
    Bridge.compile(bridge, Paths.get("scenes/cornell-box/cornell-box.xml"), dir, "primary", Seq("--bvh", "4"))
    val pkg = ScenePackage.load(dir)
    val cfg = AccelConfig(
      numRayIds = 16,
      stackDepth = 24,
      maxNodes = 1 << 14,
      maxTriangles = 1 << 13,
      maxLeafSize = 4,
      layout = BvhLayout.Wide(4)
    )
    assert(pkg.misfits(cfg).isEmpty, pkg.misfits(cfg))
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Nearest)
    // Every 16th camera ray: the whole image's spread in 256 rays.
    val phase = rnd.nextInt(16)
    val rays = pkg.rays.indices.filter(_ % 16 == phase).map(pkg.rays)
    val lay = SystemHarness.layout(pkg.image, rays.size, skew = 1)
    test(new SystemSimTop(SystemConfig(core = cfg, cores = 1), dp)).withAnnotations(Backends.verilator) { dut =>
      val h = new SystemHarness(
        dut,
        AxiMemoryParams(latency = LatencyNs(100, 200), readyProb = 0.9, validProb = 0.9, seed = rnd.nextLong())
      )
      h.put(lay.sceneBase, pkg.image.bytes)
      assert(h.loadScene(lay.sceneBase) == 0)
      batch(h, cfg, pkg.image, FloatGolden(dp), rays, lay, _ => 0, "cornell primary FP32, 1 core")
    }
  }
}
