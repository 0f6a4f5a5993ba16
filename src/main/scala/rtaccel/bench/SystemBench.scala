package rtaccel.bench

import chiseltest.RawTester.test
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.golden.TraversalGolden
import rtaccel.scene.ScenePackage
import rtaccel.AccelConfig
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{Backends, SystemHarness, SystemSimTop}
import rtaccel.sim.axi.AxiMemoryParams
import rtaccel.system.SystemConfig

import java.nio.file.{Files, Paths, StandardOpenOption}

/** `make system-bench`: rays per cycle of the whole system (N cores, the
  * MemoryFabric and its node store, the DMAs) on a compiled scene package,
  * under the AXI memory model at the PL DDR3's settings (100 ns, 12.8 GB/s at
  * a 200 MHz fabric clock). Cycle counts, not time; every hit is checked
  * against the golden model. Appends a row to build/bench/system.md.
  * Args: --package DIR --cores N [--rays K (first K rays)] [--ids 64].
  */
object SystemBench {
  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val dir = Paths.get(kv.getOrElse(
      "--package",
      throw new IllegalArgumentException("--package DIR (a compiled 4-wide package) is required")
    ))
    val pkg = ScenePackage.load(dir)
    val cores = kv.getOrElse("--cores", "1").toInt
    val rays = pkg.rays.take(kv.get("--rays").map(_.toInt).getOrElse(pkg.rays.size))
    val cfg = pkg.sized(AccelConfig(
      numRayIds = kv.get("--ids").fold(AccelConfig.zc706.numRayIds)(_.toInt),
      layout = BvhLayout.Wide(4)
    ))
      .withFloat(FloatFormat.FP32).copy(addrBits = 32)
    require(pkg.misfits(cfg).isEmpty, s"$dir: ${pkg.misfits(cfg)}")
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
    val golden = FloatGolden(dp)
    val sys = SystemConfig(core = cfg, cores = cores)
    test(new SystemSimTop(sys, dp), Backends.verilator) { dut =>
      val h = new SystemHarness(dut, AxiMemoryParams(seed = 1))
      val lay = SystemHarness.layout(pkg.image, rays.size, skew = 0)
      h.put(lay.sceneBase, pkg.image.bytes)
      require(h.loadScene(lay.sceneBase, limit = 10000000) == 0, "scene load failed")
      h.putRays(lay.rayBase, rays.indices.map(i => rays(i).copy(number = i.toLong)))
      h.write("CTRL", 4)
      h.runBatch(lay.rayBase, rays.size, lay.hitBase, limit = 100000000L)
      var bad = 0
      for (i <- rays.indices) {
        val (hw, _) = h.hitRecord(lay.hitBase, i)
        val r = rays(i).copy(number = i.toLong)
        if (!TraversalGolden.agrees(r, hw, TraversalGolden.trace(cfg, pkg.image, golden, r).hit)) bad += 1
      }
      val cycles = h.read64("CYCLES").toDouble
      val (hits, misses) = (h.read64("NODE_STORE_HITS").toDouble, h.read64("NODE_STORE_MISSES").toDouble)
      val beats = h.read64("AXI_READ_BEATS").toDouble
      val row =
        f"| ${dir.getFileName} | $cores | ${cfg.numRayIds} | ${rays.size} | $cycles%,.0f | ${rays.size / cycles}%.4f | " +
          f"${100 * hits / (hits + misses).max(1)}%.1f%% | ${beats / cycles}%.3f | $bad |"
      println(s"system-bench: $row")
      val out = Paths.get("build/bench/system.md")
      Files.createDirectories(out.getParent)
      if (!Files.exists(out)) Files.writeString(
        out,
        "# System rays/cycle (chiseltest, AXI model: 100 ns, 12.8 GB/s at 200 MHz; cycle counts, estimates of nothing else)\n\n" +
          "| package | cores | ray IDs/core | rays | cycles | rays/cycle | node store hit rate | R beats/cycle (max 1) | golden mismatches |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n"
      )
      Files.writeString(out, row + "\n", StandardOpenOption.APPEND)
      require(bad == 0, s"$bad rays differ from the golden model")
    }
  }
}
