package rtaccel.regress

import chisel3._
import chiseltest._
import firrtl2.options.TargetDirAnnotation
import rtaccel.AccelConfig
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.mem.Latency
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.system.{AccelHarness, Environment, SimTop}

import java.nio.file.{Files, Paths}

/** `make bench`: speed of the FP32 watertight accelerator on the Cornell box
  * and the ~200k-triangle dragon, camera / shadow / AO rays, memory latency
  * 10 and 100, against the analytic bound; then the number of rays in flight
  * needed to hold the bound. Every run is also checked ray by ray against the
  * golden model (a mismatch fails the bench) and judged against Embree.
  * Writes docs/performance.md and build/bench/bench.json.
  */
object Bench {
  private val bridge = Paths.get("nori-bridge/target/release/nori-bridge")
  private val root = Paths.get("build/bench")

  private def pkg(scene: String, rays: String): ScenePackage = {
    val dir = root.resolve(s"${Paths.get(scene).getFileName.toString.stripSuffix(".xml")}-$rays")
    Bridge.compile(bridge, Paths.get(scene), dir, rays)
    ScenePackage.load(dir)
  }

  def main(args: Array[String]): Unit = {
    val out = Paths.get(args.headOption.getOrElse("docs/performance.md"))
    val t0 = System.nanoTime()
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Nearest)
    val chosen: Chosen[Data, Any] = Chosen(dp, FloatGolden(dp)).asInstanceOf[Chosen[Data, Any]]
    val scenes = Seq("cornell-box" -> "scenes/cornell-box/cornell-box.xml", "dragon" -> "scenes/dragon/dragon.xml")
    val packages = for ((name, xml) <- scenes; rays <- Seq("primary", "shadow", "ao")) yield (name, rays, pkg(xml, rays))
    val rows = collection.mutable.ArrayBuffer.empty[ujson.Obj]

    def runAll(ids: Int, cases: Seq[(String, String, ScenePackage, Int, Option[Int])]): Unit = {
      val cfg = AccelConfig(numRayIds = ids, float = dp.fmt)
      val annos = Seq(VerilatorBackendAnnotation, chiseltest.internal.CachingAnnotation,
        TargetDirAnnotation(s"build/sim/SimTop_${chosen.dp.name}_n${ids}_d${cfg.stackDepth}"))
      RawTester.test(new SimTop(cfg, chosen.dp), annos) { dut =>
        for ((scene, kind, p, latency, limit) <- cases) {
          val rays = limit.fold(p.rays)(n => p.rays.take(n))
          require(p.misfits(cfg).isEmpty, s"$scene: ${p.misfits(cfg)}")
          val a = RegressArgs(p.dir, root, memLatency = Latency.Fixed(latency), numRayIds = ids)
          dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
          val wall = System.nanoTime()
          val r = AccelHarness.run(dut, p.image, rays, Environment(a.memory(0), a.memory(1)))
          val sim = (System.nanoTime() - wall) / 1e9
          val bad = Regress.goldenCheck(cfg, p, rays, chosen, r.hits)
          require(bad.isEmpty, s"$scene $kind: ${bad.size} rays differ from the golden model")
          val outDir = root.resolve(s"$scene-$kind-L$latency-n$ids")
          HitsCsv.write(outDir.resolve("hits.csv"), r.hits)
          val acc = if (limit.isEmpty) Some(Bridge.compare(bridge, p.dir, outDir, 24)) else None
          val s = Report.stats(a, cfg, chosen.dp.name, rays.size, r, sim, sim, 0, r.hits.count(_.errors != 0))
          s("scene") = scene; s("rays kind") = kind; s("latency") = latency
          s("embreeMismatches") = acc.fold[ujson.Value](ujson.Num(-1))(_("mismatches"))
          rows += s
          println(f"bench: $scene%-12s $kind%-8s L=$latency%-4d ids=$ids%-4d ${rays.size}%6d rays ${r.cycles}%,10d cycles " +
            f"${s("raysPerCycle").num}%.4f r/c (bound ${s("boundRaysPerCycle").num}%.4f, ${s("efficiency").num}%.2f) ${s("simulation")("cyclesPerSecond").num}%.0f c/s")
        }
      }
    }
    runAll(64, for ((s, k, p) <- packages; l <- Seq(10, 100)) yield (s, k, p, l, None))
    val dragonAo = packages.find(x => x._1 == "dragon" && x._2 == "ao").get
    for (ids <- Seq(8, 16, 32, 128)) runAll(ids, Seq((dragonAo._1, dragonAo._2, dragonAo._3, 100, Some(1500))))
    runAll(64, Seq((dragonAo._1, dragonAo._2, dragonAo._3, 100, Some(1500))))

    Files.createDirectories(root)
    Files.writeString(root.resolve("bench.json"), ujson.write(ujson.Arr(rows.toSeq: _*), indent = 2))
    Files.writeString(out, BenchMarkdown(rows.toSeq, (System.nanoTime() - t0) / 1e9))
    println(s"bench: wrote $out")
  }
}
