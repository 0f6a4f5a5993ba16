package rtaccel.bench

import chisel3._
import chiseltest._
import firrtl2.options.TargetDirAnnotation
import rtaccel.AccelConfig
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.sweep.{GoldenHits, SpeedRuns, SweepPoint}
import rtaccel.bvh.BvhLayout
import rtaccel.regress.{Bridge, Cli, Regress, RegressArgs, Report}
import rtaccel.sim.{AccelHarness, SimTop}

import java.nio.file.{Files, Path, Paths}

/** `make bench`: one side-by-side table of the FP32 watertight accelerator
  * (conservative boxes, as `make regress` builds it) over BVH layouts x
  * memory (on chip, DDR) x ray sets. Each run simulates at most `maxRays`
  * rays, strided over the set, and checks every one bit for bit against the
  * golden model (a mismatch fails the bench); Embree mismatches are counted
  * on every ray of the set, with the golden model's answers (the hardware's,
  * bit for bit, as the simulated sample shows). Writes the table (by default
  * docs/reports/performance.md) and build/bench/bench.json.
  */
object Bench {
  final case class Run(scene: String, xml: String, rays: String) { def name = s"$scene-$rays" }
  val Runs: Seq[Run] = Seq(
    Run("cornell-box", "scenes/cornell-box/cornell-box.xml", "primary"),
    Run("dragon", "scenes/dragon/dragon.xml", "primary"),
    Run("dragon", "scenes/dragon/dragon.xml", "shadow"),
    Run("dragon", "scenes/dragon/dragon.xml", "ao"),
    // The second large scene, of another kind (docs/dram-traffic.md): fetched by make bridge-scenes-monastery.
    Run("monastery", "scenes/monastery/monastery.xml", "primary"),
    Run("monastery", "scenes/monastery/monastery.xml", "shadow"),
    Run("monastery", "scenes/monastery/monastery.xml", "ao")
  )
  val Memories: Seq[String] = Seq("onchip", "ddr")

  /** nori-bridge's own layout: binary nodes of 32 bytes, what the RTL on this branch reads. */
  val DefaultLayout = "nori"

  final case class Args(
      layouts: Seq[String] = Seq(DefaultLayout),
      runs: Seq[Run] = Runs,
      maxRays: Int = 2048,
      out: Path = Paths.get("docs/reports/performance.md"),
      area: Path = Paths.get("build/bench/area.json"),
      bridge: Path = Paths.get("nori-bridge/target/release/nori-bridge"),
      threads: Int = 2,
      /** Only redraw the table from `rows` (after a run, e.g. with new area figures). */
      renderOnly: Boolean = false,
      /** The per-core rows of the last run (and beside it, `<name>-run.json`: its commit, time and seconds). A table
        * of its own (make bench-quant) keeps its own, so that one target never redraws another's rows. */
      rows: Path = Paths.get("build/bench/bench.json"),
      /** The system section (BenchSystem): the system top for 1, 2, 4 and the cores that fit, under the C++ harness:
        * "1" measures it, "0" leaves it out, "cached" redraws it from build/bench/system.json against what
        * build/verilog/resources.md says now (cores that fit, Fmax estimate), "embree" does the same after
        * re-measuring only Embree (with the load average). */
      system: String = "1",
      /** What `make verilog` wrote: the cores that fit and the Fmax estimate (VerilogFigures). */
      verilog: Path = Paths.get("build/verilog/resources.md"),
      /** BOX_TEST=: how the cores test child boxes (fp32, or grid for the quantized layouts 4q and 8q). */
      boxTest: rtaccel.BoxTest = rtaccel.BoxTest.Fp32,
      /** BVH=: the node layout of the system section's cores (what `make verilog BVH=` built); `boxTest` applies too. */
      systemLayout: String = BenchSystem.DefaultLayout
  )

  val usage = "usage: Bench [--out docs/reports/performance.md] [--layouts nori,2,4,8] [--runs cornell-box-primary,dragon-ao,...] " +
    "[--max-rays 2048] [--area build/bench/area.json] [--threads 2] [--render-only 0|1] [--system 0|1|cached|embree] " +
    "[--verilog build/verilog/resources.md] [--rows build/bench/bench.json] [--box-test fp32|grid] [--system-layout 4|4q|...]"

  val SystemModes: Seq[String] = Seq("0", "1", "cached", "embree")

  def parse(args: Seq[String]): Args = {
    def fail(why: String): Nothing = throw new IllegalArgumentException(s"$why\n$usage")
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    args.grouped(2).map(p => p(0) -> p(1)).foldLeft(Args()) { case (a, (k, v)) =>
      def list = v.split(',').map(_.trim).filter(_.nonEmpty).toSeq
      def int = v.toIntOption.filter(_ >= 1).getOrElse(fail(s"$k: '$v' is not a whole number >= 1"))
      k match {
        case "--out"     => a.copy(out = Paths.get(v))
        case "--layouts" => if (list.isEmpty) fail(s"--layouts: '$v' names no layout") else a.copy(layouts = list)
        case "--runs" => a.copy(runs =
            list.map(n =>
              Runs.find(_.name == n)
                .getOrElse(fail(s"--runs: '$n' is not one of ${Runs.map(_.name).mkString(", ")}"))
            )
          )
        case "--max-rays"    => a.copy(maxRays = int)
        case "--area"        => a.copy(area = Paths.get(v))
        case "--threads"     => a.copy(threads = int)
        case "--render-only" => a.copy(renderOnly = v == "1")
        case "--system" =>
          if (SystemModes.contains(v)) a.copy(system = v) else fail(s"--system: '$v' (${SystemModes.mkString(", ")})")
        case "--verilog"       => a.copy(verilog = Paths.get(v))
        case "--system-layout" => a.copy(systemLayout = v)
        case "--box-test" =>
          a.copy(boxTest =
            try rtaccel.BoxTest.parse(v)
            catch { case e: IllegalArgumentException => fail(s"--box-test: ${e.getMessage}") }
          )
        case "--rows" =>
          if (v.endsWith(".json")) a.copy(rows = Paths.get(v)) else fail(s"--rows: '$v' is not a .json file")
        case other => fail(s"unknown option '$other'")
      }
    }
  }

  /** The hand-written reading kept beside a generated page: docs/reports/performance.md's is docs/reports/performance-notes.md. */
  def notesFor(out: Path): Path = out.resolveSibling(out.getFileName.toString.stripSuffix(".md") + "-notes.md")

  /** The hardware that reads `layout`'s nodes: the ZC706 configuration with its box lanes (and `boxTest`'s box unit). */
  def configFor(layout: String, boxTest: rtaccel.BoxTest = rtaccel.BoxTest.Fp32): AccelConfig = {
    val l =
      try BvhLayout.parse(layout)
      catch { case e: IllegalArgumentException => throw new IllegalArgumentException(s"--layouts: ${e.getMessage}") }
    try AccelConfig.zc706.copy(layout = l, boxTest = boxTest)
    catch {
      case e: IllegalArgumentException => throw new IllegalArgumentException(s"--layouts $layout: ${e.getMessage}")
    }
  }

  /** Where the bench keeps its packages, rows and caches. */
  val root: Path = Paths.get("build/bench")

  def main(args: Array[String]): Unit = Cli.orExit(run(parse(args.toSeq)))

  /** The datapath the bench simulates: FP32 with the regression's default triangle test and box rounding. */
  def datapath: FloatDatapath = {
    val base = RegressArgs(root, root)
    FloatDatapath(FloatFormat.FP32, TriangleTest.parse(base.triangle), BoxRounding.parse(base.rounding))
  }

  def run(a: Args): Unit = {
    val t0 = System.nanoTime()
    val dp = datapath
    val golden = FloatGolden(dp)
    // Refuse an unknown layout (or one BOX_TEST= cannot read) before any work.
    a.layouts.foreach(configFor(_, a.boxTest))
    if (a.system != "0") configFor(a.systemLayout, a.boxTest)
    // The system section first (the C++ harness is quick, and a missing make verilog shows at once):
    // measured now, or redrawn from its cache (after re-measuring Embree alone with "embree").
    val systemJson = BenchSystem.cacheFile(a)
    def cached() = {
      if (!Files.exists(systemJson))
        throw new IllegalArgumentException(s"--system ${a.system}: $systemJson is missing (run with --system 1)")
      BenchSystem.fromJson(ujson.read(Files.readString(systemJson)))
    }
    def save(r: BenchSystem.Result) = {
      Files.createDirectories(root)
      Files.writeString(systemJson, ujson.write(BenchSystem.toJson(r), indent = 2))
      r
    }
    val system = a.system match {
      case "0"      => None
      case "cached" => Some(BenchSystem.redraw(a, dp, cached()))
      case "embree" => Some(BenchSystem.redraw(a, dp, save(BenchSystem.remeasureEmbree(a, cached(), root))))
      case _        => Some(save(BenchSystem.run(a, dp, golden, root)))
    }
    val benchJson = a.rows
    // <rows>-run.json: the commit, time and wall seconds of the run that wrote the rows, for a redrawn table's header.
    val runJson = Paths.get(a.rows.toString.stripSuffix(".json") + "-run.json")
    val rows =
      if (a.renderOnly) {
        if (!Files.exists(benchJson)) throw new IllegalArgumentException(
          s"--render-only 1: $benchJson is missing (run `make bench` with BENCH_RENDER_ONLY=0)"
        )
        ujson.read(Files.readString(benchJson)).arr.map(_.obj).map(o => ujson.Obj.from(o)).toSeq
      } else {
        val p = BenchSystem.provenance()
        val rs = for (layout <- a.layouts; row <- runLayout(a, layout, dp, golden)) yield row
        Files.createDirectories(benchJson.toAbsolutePath.getParent)
        Files.writeString(benchJson, ujson.write(ujson.Arr(rs: _*), indent = 2))
        Files.writeString(
          runJson,
          ujson.write(
            ujson.Obj("commit" -> p.commit, "at" -> p.at, "seconds" -> (System.nanoTime() - t0) / 1e9),
            indent = 2
          )
        )
        rs
      }
    val earlier = Option.when(a.renderOnly && Files.exists(runJson)) {
      val j = ujson.read(Files.readString(runJson))
      f"the run at commit ${j("commit").str} (${j("at").str}, ${j("seconds").num}%.0f s)"
    }
    // Box-lane LUTs per layout: K lanes of the datapath's box unit, each synthesised
    // alone by Yosys (cached in build/area-cache with make verilog's results).
    val area = rows.map(_("layout").str).distinct.map { layout =>
      val cfg = configFor(layout, a.boxTest).copy(boxFloat = dp.boxFmt, triFloat = dp.triFmt)
      layout -> (if (cfg.gridBox)
                   rtaccel.tools.AccelArea.gridUnit(dp, cfg, rtaccel.tools.EmitVerilog.areaCache).lut.toDouble
                 else cfg.boxLanes * rtaccel.tools.AccelArea.boxLane(
                   dp,
                   cfg,
                   rtaccel.tools.EmitVerilog.areaCache
                 ).lut.toDouble)
    }.toMap
    Files.createDirectories(a.area.toAbsolutePath.getParent)
    Files.writeString(a.area, ujson.write(ujson.Obj.from(area.map { case (k, v) => k -> ujson.Num(v) }), indent = 2))
    Files.createDirectories(a.out.toAbsolutePath.getParent)
    Files.writeString(
      a.out,
      BenchMarkdown(
        rows,
        area,
        a.maxRays,
        if (a.renderOnly) -1 else (System.nanoTime() - t0) / 1e9,
        system.fold("")(BenchSystemMarkdown(_, a.maxRays)),
        earlier.getOrElse("an earlier run"),
        notesFor(a.out),
        Option.unless(BenchSystem.isDefault(a) || a.system == "0")(
          s"Performance of a system of ${a.systemLayout} nodes with ${a.boxTest.name} box tests " +
            s"(`make bench${BenchSystem.makeVars(a.systemLayout, a.boxTest.name)}`)"
        )
      )
    )
    println(s"bench: wrote ${a.out}")
  }

  private def runLayout(a: Args, layout: String, dp: FloatDatapath, golden: FloatGolden): Seq[ujson.Obj] = {
    val loaded = a.runs.map { run =>
      val dir = root.resolve(layout).resolve(run.name)
      // The default layout is nori-bridge's default: asked for by name only once `--bvh` exists there.
      Bridge.compile(a.bridge, Paths.get(run.xml), dir, run.rays, bvh = Option.when(layout != DefaultLayout)(layout))
      (run, ScenePackage.load(dir))
    }
    // One build per layout for every run: its stack is the ZC706 default, or deeper where a run's BVH needs it (the
    // monastery's 8-wide tree pushes up to 7 children a level), as `make verilog SCENE=` would size it.
    val generic = configFor(layout, a.boxTest)
    val cfg = generic.copy(stackDepth = (generic.stackDepth +: loaded.map(_._2.needs.bvhDepth)).max)
    val packages = loaded.map { case (run, p) =>
      require(p.misfits(cfg).isEmpty, s"${run.name} ($layout): ${p.misfits(cfg).mkString("; ")}")
      // Every ray through the golden model, then against Embree.
      val g = GoldenHits.run(cfg, p.image, golden, p.rays, a.threads)
      val out = root.resolve(layout).resolve(s"${run.name}-golden")
      HitsCsv.write(out.resolve("hits.csv"), g.hits)
      val embree = Bridge.compare(a.bridge, p.dir, out, dp.fmt.manBits + 1)("mismatches").num.toLong
      (run, p, g.hits.map(h => h.number -> h).toMap, embree)
    }
    val rows = collection.mutable.ArrayBuffer.empty[ujson.Obj]
    val annos = Seq(
      VerilatorBackendAnnotation,
      chiseltest.internal.CachingAnnotation,
      TargetDirAnnotation(
        Regress.simDir(
          dp.name,
          cfg,
          (if (layout == DefaultLayout) "" else s"_$layout") + (if (cfg.gridBox) "_grid" else "")
        ).toString
      )
    )
    RawTester.test(new SimTop(cfg, dp), annos) { dut =>
      for ((run, p, goldenHits, embree) <- packages; memory <- Memories) {
        val rays = SpeedRuns.sample(p.rays, a.maxRays)
        val args = RegressArgs(p.dir, root, memory = memory, numRayIds = cfg.numRayIds)
        dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
        val wall = System.nanoTime()
        val r = AccelHarness.run(dut, p.image, rays, args.environment)
        val sim = (System.nanoTime() - wall) / 1e9
        val bad = SweepPoint.sameAnswers(rays.map(x => x.number -> x).toMap, r.hits, goldenHits)
        require(bad == 0, s"${run.name} $layout $memory: $bad of ${rays.size} rays differ from the golden model")
        val s = Report.stats(args, cfg, dp.name, rays.size, r, sim, sim, bad, r.hits.count(_.errors != 0))
        s("layout") = layout; s("run") = run.name; s("memoryKind") = memory; s("boxTest") = cfg.boxTest.name
        s("raySetSize") = p.rays.size; s("embreeMismatches") = embree.toDouble
        rows += s
        println(
          f"bench: ${run.name}%-20s $layout%-5s $memory%-6s ${rays.size}%5d rays ${r.cycles}%,9d cycles " +
            f"${s("raysPerCycle").num}%.4f r/c (${s("efficiency").num}%.2f of ${s("boundRaysPerCycle").num}%.4f, ${s("boundLimitedBy").str})"
        )
      }
    }
    rows.toSeq
  }
}
