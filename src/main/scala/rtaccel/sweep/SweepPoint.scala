package rtaccel.sweep

import chisel3._
import rtaccel.datapath.{FloatDatapath, FloatGolden}
import rtaccel.golden.HitRecord
import rtaccel.regress.Bridge
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.AccelConfig
import rtaccel.report.DatapathArea

import java.nio.file.{Files, Path}

/** One point of `make speed-vs-error` (one command line, so a scheduler can
  * spread the points over machines): for one configuration, every ray of
  * every run through the golden model (hits.csv, then `nori-bridge compare`
  * against the package's reference, or `hard-score` against a hard case's
  * expectations), the RTL on the speed runs (rays/cycle against the bound,
  * every simulated ray checked against the golden answer), and the unit
  * latencies. Writes `<sweep>/points/<name>.json` for `nori-bridge sweep-report`.
  */
object SweepPoint {
  def main(args: Array[String]): Unit = rtaccel.regress.Cli.orExit(run(SweepArgs.parse(args.toSeq)))

  def run(a: SweepArgs): Unit = {
    val t0 = System.nanoTime()
    val golden = FloatGolden(a.dp)
    val packages = a.runs.map(r => r -> ScenePackage.load(a.packageDir(r))).toMap
    // The packages' node layout (nori-bridge compile --bvh) must be the point's.
    for ((r, p) <- packages if p.image.layout != a.layout)
      throw new IllegalArgumentException(
        s"${p.dir}: compiled with ${p.image.layout.name} nodes, but the point is ${a.layout.name}"
      )
    val cfg = a.config
    // The numeric range is not checked here: where a narrow format cannot hold a
    // scene's range is exactly what the sweep measures (`in_range` per run).
    for ((r, p) <- packages; why <- p.structuralMisfits(cfg).headOption)
      throw new IllegalArgumentException(s"${p.dir}: does not fit the generic configuration: $why")

    val entries = a.runs.map { run =>
      val p = packages(run)
      val t = System.nanoTime()
      val g = GoldenHits.run(cfg, p.image, golden, p.rays, a.threads)
      HitsCsv.write(a.hitsFile(run), g.hits)
      val judged = judge(a, run, p)
      println(f"sweep ${a.name}: $run: ${p.rays.size}%,d rays in ${(System.nanoTime() - t) / 1e9}%.1f s")
      run -> (g, judged)
    }.toMap

    val speed = SpeedRuns.measure(
      a,
      cfg,
      a.speedRuns.map(r => r -> packages(r)),
      a.speedRuns.map(r => r -> entries(r)._1.hits.map(h => h.number -> h).toMap).toMap
    )

    val runs = a.runs.map { run =>
      val p = packages(run)
      val (g, judged) = entries(run)
      val manifest = ujson.read(Files.readString(p.dir.resolve("package.json")))
      val scene = java.nio.file.Paths.get(manifest("source_scene").str).getFileName.toString.stripSuffix(".xml")
      val o = ujson.Obj(
        "run" -> run,
        "scene" -> scene,
        "rays" -> manifest("ray_kind").str,
        "hard_case" -> hardCase(run).fold[ujson.Value](ujson.Null)(ujson.Str(_)),
        "package" -> p.dir.toString,
        "hits" -> a.hitsFile(run).toString,
        "rays_total" -> p.rays.size,
        "in_range" -> Seq(a.boxFmt, a.triFmt).forall(f => p.range.misfit(f).isEmpty),
        "exp_bits_needed" -> p.range.expBits,
        "error_flagged" -> g.hits.count(_.errors != 0),
        "node_tests_per_ray" -> g.perRay(g.boxTests),
        "tri_tests_per_ray" -> g.perRay(g.triTests),
        // Every box test is one node fetch (TraversalGolden: a node's K slots in one test).
        "node_bytes_per_ray" -> g.perRay(g.boxTests) * p.image.nodeBytes.toDouble,
        "speed" -> speed.getOrElse(run, ujson.Null)
      )
      o(if (hardCase(run).isDefined) "hard" else "accuracy") = judged
      o
    }
    val point = ujson.Obj(
      "config" -> ujson.Obj(
        "name" -> a.name,
        "float" -> FloatDatapath.formatsName(a.boxFmt, a.triFmt),
        "exp_bits" -> a.boxFmt.expBits,
        "man_bits" -> a.boxFmt.manBits,
        "layout" -> a.layout.name,
        "box_float" -> a.boxFmt.name,
        "tri_float" -> a.triFmt.name,
        "rounding" -> (if (a.rounding.tag == "rne") "rne" else "conservative"),
        "triangle" -> (if (a.test.tag == "wt") "watertight" else "moller"),
        "box_test" -> a.boxTest.name
      ),
      "latency" -> latencies(cfg, a),
      "runs" -> ujson.Arr(runs: _*),
      "seconds" -> (System.nanoTime() - t0) / 1e9
    )
    Files.createDirectories(a.pointFile.getParent)
    Files.writeString(a.pointFile, ujson.write(point, indent = 2))
    println(f"sweep ${a.name}: wrote ${a.pointFile} in ${(System.nanoTime() - t0) / 1e9}%.0f s")
  }

  /** Mantissa bits (hidden bit included) of the tolerances every point is judged with: FP32's. */
  val judgedPrecision = 24

  /** `hard-<case>` runs are hard cases, scored against the case's expectations. */
  def hardCase(run: String): Option[String] = Option.when(run.startsWith("hard-"))(run.stripPrefix("hard-"))

  private def judge(a: SweepArgs, run: String, p: ScenePackage): ujson.Value = hardCase(run) match {
    case Some(c) =>
      val expect = a.hardDir.resolve(c).resolve("expect.csv")
      if (!Files.exists(expect))
        throw new IllegalArgumentException(s"$expect: missing (regenerate with `make hard-cases`)")
      val out = a.sweep.resolve("hard").resolve(a.name).resolve(s"$run.json")
      Bridge.hardScore(a.bridge, p.dir, a.hitsFile(run), expect, out)
    case None =>
      // Judged with FP32 tolerances whatever the format: a narrow format's extra
      // error must show as false misses/hits, not be excused as "edge" by
      // tolerances scaled to its own precision. Ties (equal t in f64) stay apart.
      Bridge.compare(
        a.bridge,
        p.dir,
        a.sweep.resolve("accuracy").resolve(a.name).resolve(run),
        SweepPoint.judgedPrecision,
        hits = Some(a.hitsFile(run))
      )
  }

  /** Each unit's derived latency, from its elaborated module (no Verilog emitted). */
  private def latencies(cfg: AccelConfig, a: SweepArgs): ujson.Obj = {
    def lat(gen: => RawModule): Int = {
      var m: RawModule = null
      _root_.circt.stage.ChiselStage.emitCHIRRTL({ m = gen; m })
      DatapathArea.latencyOf(m)
    }
    // A grid box test's latency is its whole unit's (the FP32 node stage, then the grid lanes).
    val box =
      if (cfg.gridBox) lat(a.dp.gridBox(cfg))
      else lat(a.dp.box(cfg))
    ujson.Obj("ray_prep" -> lat(a.dp.rayPrep(cfg)), "box" -> box, "triangle" -> lat(a.dp.prim(cfg)))
  }

  /** Same answer as the golden model, under the regression's agreement rule. */
  def sameAnswers(rays: Map[Long, rtaccel.golden.RayRecord], hw: Seq[HitRecord], golden: Map[Long, HitRecord]): Int =
    hw.count(h => !rtaccel.golden.TraversalGolden.agrees(rays(h.number), h, golden(h.number)))
}
