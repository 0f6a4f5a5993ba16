package rtaccel.regress

import chisel3.Data
import chiseltest._
import chiseltest.simulator.WriteVcdAnnotation
import firrtl2.options.TargetDirAnnotation
import rtaccel.golden.{HitRecord, TraversalGolden}
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.{AccelConfig, ErrorFlags, RtAccel}
import rtaccel.sim.{AccelHarness, RunResult, SimTop}

import java.nio.file.{Files, Path, Paths}

/** `make regress`: one scene package through the RTL under Verilator, with
  * the memory-system model on both ports; every ray checked bit for bit
  * against the golden model, then against Embree by `nori-bridge compare`.
  * Writes hits.csv, stats.json, accuracy.json, report.json, report.md and,
  * for camera rays, PNGs into the output directory.
  */
object Regress {
  def main(args: Array[String]): Unit = {
    val ok = Cli.orExit(run(RegressArgs.parse(args.toSeq)))
    sys.exit(if (ok) 0 else 1)
  }

  /** The configuration this run generates: the scene decides only what the user left open. */
  def config(a: RegressArgs, pkg: ScenePackage): AccelConfig = {
    def fmt(f: String) = if (f == "field") rtaccel.fp.FloatFormat.FP32 else rtaccel.fp.FloatFormat.parse(f)
    val (boxFmt, triFmt) = (fmt(RegressArgs.formats(a)._1), fmt(RegressArgs.formats(a)._2))
    // The node layout is the image's: nori-bridge chose it (make regress BVH=).
    val generic =
      try AccelConfig.zc706.copy(
          numRayIds = a.numRayIds,
          boxFloat = boxFmt,
          triFloat = triFmt,
          layout = pkg.image.layout,
          boxTest = rtaccel.BoxTest.parse(a.boxTest)
        )
      catch {
        case e: IllegalArgumentException =>
          throw new IllegalArgumentException(s"${a.pkg} (${pkg.image.layout.name} nodes): ${e.getMessage}")
      }
    val base = if (a.sized) pkg.sized(generic) else generic
    a.stackDepth.fold(base)(d => base.copy(stackDepth = d))
  }

  /** Every ray bit for bit against the golden model of the same hardware (for
    * shadow rays: the occlusion answer and error bits). Returns the mismatching
    * hits, and prints the first few.
    */
  def goldenCheck[S](
      cfg: AccelConfig,
      pkg: ScenePackage,
      rays: IndexedSeq[rtaccel.golden.RayRecord],
      c: Chosen[Data, S],
      hits: Seq[HitRecord]
  ): Seq[HitRecord] = {
    val byNumber = rays.map(r => r.number -> r).toMap
    val bad = hits.flatMap { h =>
      val r = byNumber(h.number)
      val e = TraversalGolden.trace(cfg, pkg.image, c.golden, r).hit
      val same = TraversalGolden.agrees(r, h, e)
      if (same) None else Some((h, e))
    }
    bad.take(10).foreach { case (h, e) => println(s"regress: GOLDEN MISMATCH ray ${h.number}: hardware $h, golden $e") }
    bad.map(_._1)
  }

  /** Where Verilator builds a configuration's simulator (cached: a later run of the same hardware reuses it). */
  def simDir(datapath: String, cfg: AccelConfig, suffix: String = ""): java.nio.file.Path =
    Paths.get("build", "sim", s"RtAccel_${datapath}_n${cfg.numRayIds}_d${cfg.stackDepth}$suffix")

  /** The core under chiseltest (Verilator backend) with the memory-system model on both ports. */
  private def runChiseltest[S](
      a: RegressArgs,
      pkg: ScenePackage,
      rays: IndexedSeq[rtaccel.golden.RayRecord],
      cfg: AccelConfig,
      c: Chosen[Data, S],
      t0: Long
  ): (RunResult, ujson.Obj) = {
    val simDir = Regress.simDir(c.dp.name, cfg)
    val annos =
      Seq(VerilatorBackendAnnotation, chiseltest.internal.CachingAnnotation, TargetDirAnnotation(simDir.toString)) ++
        (if (a.waves) Seq(WriteVcdAnnotation) else Nil)
    var result: RunResult = null
    var simStart = 0L
    RawTester.test(new SimTop(cfg, c.dp), annos) { dut =>
      simStart = System.nanoTime()
      val bar = new Progress("regress:", rays.size)
      result = AccelHarness.run(dut, pkg.image, rays, a.environment, progress = bar.update)
      bar.finish(result.hits.size)
    }
    val simSeconds = (System.nanoTime() - simStart) / 1e9
    if (a.waves) println(s"regress: waveform under $simDir")
    (
      result,
      ujson.Obj(
        "seconds" -> simSeconds,
        "cyclesPerSecond" -> result.cycles / simSeconds.max(1e-9),
        "wallSeconds" -> (System.nanoTime() - t0) / 1e9
      )
    )
  }

  /** Returns false when the run found a real problem (a golden mismatch, or any compare mismatch under --strict 1). */
  def run(a: RegressArgs): Boolean = {
    val pkg = ScenePackage.load(a.pkg)
    val rays = a.maxRays.fold(pkg.rays)(n => pkg.rays.take(n))
    val hw = hardware(a, pkg)
    val cfg = hw._1
    val chosen = hw._2
    Files.createDirectories(a.out)
    println(s"regress: ${rays.size} rays, ${pkg.needs.triangles} triangles, ${pkg.needs.nodes} nodes; " +
      s"${cfg.numRayIds} ray IDs, stack ${cfg.stackDepth}, ${cfg.floatName}; memory ${a.describeMemory}")
    chosen match { case c: Chosen[t, s] => runWith(a, pkg, rays, cfg, c.asInstanceOf[Chosen[Data, s]]) }
  }

  /** The configuration and datapath a run of `a` on `pkg` generates; refuses a scene the hardware cannot hold. */
  def hardware(a: RegressArgs, pkg: ScenePackage): (AccelConfig, Chosen[_ <: Data, _]) = {
    val cfg = config(a, pkg)
    val misfits = pkg.misfits(cfg)
    if (misfits.nonEmpty)
      throw new IllegalArgumentException(
        s"${a.pkg}: the scene does not fit the generated hardware:\n  " + misfits.mkString("\n  ") +
          "\n(raise the limits, e.g. STACK=<n>, or size the hardware to the scene)"
      )
    // Sized hardware may have fewer exponent bits than asked for: build the datapath in the sized format.
    val (box, tri) = RegressArgs.formats(a)
    val chosen = if (a.sized && a.float != "field")
      DatapathChoice.resolve(cfg.boxFloat.name, cfg.triFloat.name, a.triangle, a.rounding)
    else DatapathChoice.resolve(box, tri, a.triangle, a.rounding)
    (cfg, chosen)
  }

  private def runWith[S](
      a: RegressArgs,
      pkg: ScenePackage,
      rays: IndexedSeq[rtaccel.golden.RayRecord],
      cfg: AccelConfig,
      c: Chosen[Data, S]
  ): Boolean = {
    val t0 = System.nanoTime()
    val (result, simulation) = if (a.sim == "cpp") {
      val dir = CppSim.build(cfg, c.dp, clang = CppSim.useClang)
      val (r, speed) =
        CppSim.run(a, dir, pkg.image.nodeBytes.toInt, rays.size)
      speed("wallSeconds") = (System.nanoTime() - t0) / 1e9
      (r, speed)
    } else runChiseltest(a, pkg, rays, cfg, c, t0)
    simulation("harness") = a.sim
    val goldenMismatches = goldenCheck(cfg, pkg, rays, c, result.hits)

    HitsCsv.write(a.out.resolve("hits.csv"), result.hits)
    val stats = Report.stats(
      a,
      cfg,
      c.dp.name,
      rays.size,
      result,
      simulation("seconds").num,
      simulation("wallSeconds").num,
      goldenMismatches.size,
      result.hits.count(_.errors != 0)
    )
    // The harness's own count of what it simulated (SIM=cpp: every cycle, the scene load and register accesses too).
    stats("simulation") = simulation
    Files.writeString(a.out.resolve("stats.json"), ujson.write(stats, indent = 2))

    val whole = rays.size == pkg.rays.size
    val judged = if (whole) a.pkg else Bridge.firstRays(a.pkg, rays.size, a.out.resolve(s"package-first-${rays.size}"))
    val accuracy = Bridge.compare(a.bridge, judged, a.out, cfg.triFloat.manBits + 1)
    if (whole) Bridge.render(a.bridge, a.pkg, a.out)
    else println(s"regress: no images for part of a ray set (${rays.size} of ${pkg.rays.size} rays)")
    val report = Report.combine(stats, accuracy)
    Files.writeString(a.out.resolve("report.json"), ujson.write(report, indent = 2))
    Files.writeString(a.out.resolve("report.md"), Report.markdown(report))
    println(Report.table(report))
    val compareBad = accuracy.obj.get("mismatches").map(_.num.toLong).getOrElse(0L)
    goldenMismatches.isEmpty && !(a.strict && compareBad > 0)
  }
}
