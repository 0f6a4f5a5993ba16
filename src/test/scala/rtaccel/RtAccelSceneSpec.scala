package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.golden.TraversalGolden
import rtaccel.regress.Bridge
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.testutil.{Seeded, SlowTest, Waves}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{AccelHarness, Backends, Environment, SimTop}
import rtaccel.sim.mem.{CacheParams, Latency, MemoryParams}

import java.nio.file.{Path, Paths}

/** The real accelerator on real scenes: every ray bit-exact with the golden
  * model, and (in FP32) every ray judged by `nori-bridge compare` against
  * Embree, with ties, edge cases and Embree's own errors classified apart.
  * Scenes are compiled by nori-bridge here, so it must be built (make setup).
  */
class RtAccelSceneSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RtAccel on scenes"

  private val bridge = Paths.get("nori-bridge/target/release/nori-bridge")
  private val root = Paths.get("build/test-scenes")

  private def compiled(
      scene: String,
      rays: String,
      extra: Seq[String] = Nil,
      layout: BvhLayout = BvhLayout.Wide(4)
  ): ScenePackage = {
    val name = Paths.get(scene).getFileName.toString.stripSuffix(".xml")
    // Extra options' values name the package too, so two sizes of one ray set never share a directory.
    val dir =
      root.resolve((Seq(name, rays) ++ extra.filterNot(_.startsWith("--")) :+ s"bvh${layout.name}").mkString("-"))
    Bridge.compile(bridge, Paths.get(scene), dir, rays, extra ++ Seq("--bvh", layout.name))
    ScenePackage.load(dir)
  }

  private val cfg32 = AccelConfig(
    numRayIds = 16,
    stackDepth = 24,
    maxNodes = 1 << 14,
    maxTriangles = 1 << 13,
    maxLeafSize = 4,
    layout = BvhLayout.Wide(4)
  )

  private def runScenes(
      cfg: AccelConfig,
      dp: FloatDatapath,
      cases: Seq[(String, () => ScenePackage, Environment)],
      embreeStrict: Boolean,
      seed: String
  ): Unit = Seeded(seed) { rnd =>
    val golden = FloatGolden(dp)
    Waves.onFailure(Backends.verilator) { annos =>
      test(new SimTop(cfg, dp)).withAnnotations(annos) { dut =>
        for (((what, mk, env), k) <- cases.zipWithIndex) {
          val pkg = mk()
          assert(pkg.misfits(cfg).isEmpty, s"$what: ${pkg.misfits(cfg)}")
          dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
          val run = AccelHarness.run(dut, pkg.image, pkg.rays, env.copy(seed = rnd.nextLong() + k))
          val byNumber = pkg.rays.map(r => r.number -> r).toMap
          for (h <- run.hits) {
            val r = byNumber(h.number)
            val e = TraversalGolden.trace(cfg, pkg.image, golden, r).hit
            val same = TraversalGolden.agrees(r, h, e)
            assert(same, s"$what: ray ${h.number}: hardware $h, golden $e")
          }
          val out = pkg.dir.resolve(s"hits-${dp.name}")
          HitsCsv.write(out.resolve("hits.csv"), run.hits)
          val acc = Bridge.compare(bridge, pkg.dir, out, dp.triFmt.manBits + 1)
          val bad = acc("mismatches").num.toLong
          println(
            f"$what (${dp.name}): ${pkg.rays.size} rays in ${run.cycles}%,d cycles, golden exact; vs Embree ${acc("counts")}"
          )
          if (embreeStrict) assert(
            bad == 0,
            s"$what: $bad rays disagree with Embree beyond ties and edge cases; see $out/accuracy.json"
          )
        }
      }
    }
  }

  private val lat100 = Environment(MemoryParams(Latency.Fixed(100)), MemoryParams(Latency.Fixed(100)))
  private val ooo = Environment(
    MemoryParams(Latency.Uniform(50, 300), maxOutstanding = 12),
    MemoryParams(Latency.Uniform(50, 300), maxOutstanding = 12),
    rayGap = 0.2,
    hitRefuse = 0.3,
    memRefuse = 0.2
  )
  private val cached = Environment(
    MemoryParams(Latency.Fixed(60), cache = Some(CacheParams())),
    MemoryParams(Latency.Fixed(60), cache = Some(CacheParams()))
  )

  it should "match the golden model and Embree in FP32 (watertight, 4-wide nodes) on camera, shadow, AO and random rays" in {
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Nearest)
    runScenes(
      cfg32,
      dp,
      Seq(
        ("cornell primary", () => compiled("scenes/cornell-box/cornell-box.xml", "primary"), lat100),
        ("cornell shadow", () => compiled("scenes/cornell-box/cornell-box.xml", "shadow"), ooo),
        ("cornell AO", () => compiled("scenes/cornell-box/cornell-box.xml", "ao"), cached),
        ("icosphere random", () => compiled("scenes/icosphere/icosphere.xml", "random", Seq("--count", "3000")), ooo),
        (
          "multi-mesh AO",
          () => compiled("scenes/multi-mesh/multi-mesh.xml", "ao", Seq("--width", "40", "--height", "30")),
          lat100
        )
      ),
      embreeStrict = true,
      "RtAccelScene.fp32"
    )
  }

  // A whole-core build each (about a minute), so `make test-slow`, not `make test`: in `make test` the 2-, 8- and
  // 4q-wide layouts are covered by RtAccelControlSpec (every ray golden-exact under random back-pressure), the
  // unit specs (BboxIntersect's quantized decode, Traversal's 4q walk) and the 4q cases below (split and grid
  // box tests, against Embree); `make bench` runs layouts 2 and 8 on every scene against the golden model and Embree.
  for (layout <- Seq(BvhLayout.Wide(2), BvhLayout.Wide(8), BvhLayout.Wide(4, quantized = true)))
    it should s"match the golden model and Embree in FP32 with ${layout.name}-wide nodes and conservative boxes on the Cornell box, sized to it" taggedAs SlowTest in {
      val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
      // Sized: the stack holds exactly the layout's bound (the header's bvhDepth), indices the node and triangle counts.
      val primary = compiled("scenes/cornell-box/cornell-box.xml", "primary", layout = layout)
      val cfg = primary.sized(cfg32)
      assert(
        cfg.layout == layout && cfg.stackDepth == primary.image.bvhDepth && cfg.maxNodes == primary.needs.nodes,
        cfg
      )
      runScenes(
        cfg,
        dp,
        Seq(
          ("cornell primary", () => compiled("scenes/cornell-box/cornell-box.xml", "primary", layout = layout), ooo),
          ("cornell AO", () => compiled("scenes/cornell-box/cornell-box.xml", "ao", layout = layout), lat100)
        ),
        embreeStrict = true,
        s"RtAccelScene.wide${layout.name}"
      )
    }

  it should "match the golden model bit for bit on hardware sized to the Cornell box (nori nodes, narrow, Moller-Trumbore, conservative boxes)" in {
    // Sized from e8m12: layout, stack, indices and leaf size from the BVH, exponent bits from the numeric range.
    val primary = compiled("scenes/cornell-box/cornell-box.xml", "primary", layout = BvhLayout.Nori)
    val cfg = primary.sized(cfg32.withFloat(FloatFormat(8, 12)))
    assert(
      cfg.boxFloat == FloatFormat(7, 12) && cfg.triFloat == FloatFormat(
        7,
        12
      ) && cfg.stackDepth == primary.needs.bvhDepth && cfg.maxLeafSize == primary.needs.largestLeaf,
      cfg
    )
    val dp = FloatDatapath.of(cfg, TriangleTest.Moller, BoxRounding.Conservative)
    runScenes(
      cfg,
      dp,
      Seq(
        ("cornell primary", () => primary, ooo),
        ("cornell AO", () => compiled("scenes/cornell-box/cornell-box.xml", "ao", layout = BvhLayout.Nori), cached)
      ),
      embreeStrict = false,
      "RtAccelScene.sized"
    )
  }

  it should "trace narrow conservative boxes (e8m10) with FP32 watertight triangles bit-exact with the golden model, and answer every ray as FP32 does (4q nodes, Cornell box)" in {
    // Split formats: the box lanes bound the FP32 ray outward in e8m10 and tmax
    // is narrowed up, so no box the FP32 ray reaches is culled; the triangle test is FP32's.
    // So, by construction, every answer equals the FP32 datapath's: checked per ray here.
    val layout = BvhLayout.Wide(4, quantized = true)
    // 32 x 32 camera rays: the Verilator build dominates; make test's budget for this check is about a minute.
    val primary =
      compiled("scenes/cornell-box/cornell-box.xml", "primary", Seq("--width", "32", "--height", "32"), layout)
    val cfg = primary.sized(cfg32).copy(boxFloat = FloatFormat(8, 10), triFloat = FloatFormat.FP32)
    val dp = FloatDatapath.of(cfg, TriangleTest.Watertight, BoxRounding.Conservative)
    assert(dp.name == "e8m10e8m23_wt_cons" && FloatDatapath.parse(dp.name) == dp, dp.name)
    runScenes(cfg, dp, Seq(("cornell primary", () => primary, ooo)), embreeStrict = true, "RtAccelScene.split")
    val fp32 = FloatGolden(FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative))
    val split = FloatGolden(dp)
    var (falseMiss, falseHit, wrongPrim, tDiff, moreBoxTests) = (0, 0, 0, 0, 0L)
    for (r <- primary.rays) {
      val (a, e) =
        (TraversalGolden.trace(cfg, primary.image, split, r), TraversalGolden.trace(cfg, primary.image, fp32, r))
      if (e.hit.hit && !a.hit.hit) falseMiss += 1
      if (!e.hit.hit && a.hit.hit) falseHit += 1
      if (e.hit.hit && a.hit.hit && e.hit.prim != a.hit.prim) wrongPrim += 1
      if (e.hit.hit && a.hit.hit && e.hit.prim == a.hit.prim && e.hit.t != a.hit.t) tDiff += 1
      moreBoxTests += a.boxTests - e.boxTests
    }
    println(
      s"split e8m10 boxes / FP32 triangles against FP32, ${primary.rays.size} rays: $falseMiss false misses, $falseHit false hits, " +
        s"$wrongPrim wrong prims, $tDiff t differences; ${moreBoxTests.toDouble / primary.rays.size} more box tests per ray"
    )
    assert(falseMiss == 0 && falseHit == 0 && wrongPrim == 0 && tDiff == 0)
  }

  it should "test 4q child boxes in the node's grid (BoxTest.Grid) bit-exact with the golden model, and answer every ray as FP32 box lanes do (Cornell box)" in {
    // GridBboxIntersect in place of the FP32 decode and box lanes: conservative
    // too (docs/kernels.md, "Box tests in the node's grid"), so with the same
    // FP32 watertight triangles every answer equals the FP32 box lanes' one;
    // only the traversal (extra hits, another order among siblings) differs.
    val layout = BvhLayout.Wide(4, quantized = true)
    // 32 x 32 camera rays, as the split case: the Verilator build dominates.
    val primary =
      compiled("scenes/cornell-box/cornell-box.xml", "primary", Seq("--width", "32", "--height", "32"), layout)
    val cfg = primary.sized(cfg32).copy(boxTest = BoxTest.Grid)
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
    runScenes(cfg, dp, Seq(("cornell primary", () => primary, ooo)), embreeStrict = true, "RtAccelScene.grid")
    val golden = FloatGolden(dp)
    val fp32Cfg = cfg.copy(boxTest = BoxTest.Fp32)
    var (differ, gridBoxTests, fp32BoxTests) = (0, 0L, 0L)
    for (r <- primary.rays) {
      val (g, f) =
        (TraversalGolden.trace(cfg, primary.image, golden, r), TraversalGolden.trace(fp32Cfg, primary.image, golden, r))
      if (!TraversalGolden.agrees(r, g.hit, f.hit)) differ += 1
      gridBoxTests += g.boxTests
      fp32BoxTests += f.boxTests
    }
    val n = primary.rays.size.toDouble
    println(
      f"grid box tests against FP32 box lanes, ${primary.rays.size} rays (4q): $differ answers differ; " +
        f"node tests per ray ${gridBoxTests / n}%.2f (grid), ${fp32BoxTests / n}%.2f (FP32)"
    )
    assert(differ == 0)
  }
}
