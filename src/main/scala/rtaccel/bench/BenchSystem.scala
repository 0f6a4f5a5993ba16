package rtaccel.bench

import rtaccel.AccelConfig
import rtaccel.datapath.FloatDatapath
import rtaccel.golden.{HitRecord, RayRecord}
import rtaccel.scene.{MemoryImage, ScenePackage}
import rtaccel.sweep.{GoldenHits, SpeedRuns, SweepPoint}
import rtaccel.regress.{Bridge, CppSim, RegressArgs, VerilogFigures}

import java.nio.file.{Files, Path, Paths, StandardCopyOption}
import scala.jdk.CollectionConverters._
import scala.sys.process._

/** `make bench`'s system section: rays/cycle of the system
  * top (rtaccel_system: N cores, MemoryFabric and its node store, ray and hit
  * DMA, registers) under the C++ harness (sw/sim/, the DDR model behind
  * m_axi) for N = 1, 2, 4 and the cores that fit; every simulated ray checked
  * bit for bit against the golden model. The ZC706 estimate multiplies the
  * fitting system's rays/cycle by the Fmax estimate, both read from what
  * `make verilog` wrote (VerilogFigures); Embree runs on this machine on the
  * same ray sets (`nori-bridge bench`, 2 threads).
  */
object BenchSystem {

  /** The node layout of the system's cores by default: the ZC706 configuration, 4-wide nodes (what make verilog builds
    * by default). `make bench BVH=4q BOX_TEST=grid` measures another (Bench.Args.systemLayout, boxTest).
    */
  val DefaultLayout = "4"

  /** The core every system row instantiates: the ZC706 configuration with the bench's system layout and box test. */
  def config(a: Bench.Args, dp: FloatDatapath): AccelConfig =
    Bench.configFor(a.systemLayout, a.boxTest).copy(boxFloat = dp.boxFmt, triFloat = dp.triFmt)

  /** Whether `layout` and `boxTest` are the default system's (4-wide nodes, FP32 box lanes): its cache and page keep
    * their names, and no make variable selects it. */
  def isDefault(layout: String, boxTest: String): Boolean =
    layout == DefaultLayout && boxTest == rtaccel.BoxTest.Fp32.name

  def isDefault(a: Bench.Args): Boolean = isDefault(a.systemLayout, a.boxTest.name)

  /** Where the section's measurements are cached (under build/bench, Bench.root): system.json for the default
    * system, else one file per layout and box test (system-4q-grid.json), so that measuring another system never
    * overwrites the default's. */
  def cacheName(layout: String, boxTest: String): String =
    if (isDefault(layout, boxTest)) "system.json" else s"system-$layout-$boxTest.json"

  def cacheFile(a: Bench.Args): Path = Bench.root.resolve(cacheName(a.systemLayout, a.boxTest.name))

  /** The make variables that select a system other than the default (`BVH=4q BOX_TEST=grid`), or "". */
  def makeVars(layout: String, boxTest: String): String =
    if (isDefault(layout, boxTest)) ""
    else s" BVH=$layout" + (if (boxTest == rtaccel.BoxTest.Fp32.name) "" else s" BOX_TEST=$boxTest")

  /** Core counts always measured; the cores that fit are added. */
  val Cores: Seq[Int] = Seq(1, 2, 4)

  /** Words resources.md's title must hold for its figures to be this core's. */
  def expectTitle(dp: FloatDatapath, cfg: AccelConfig): Seq[String] =
    Seq(rtaccel.tools.EmitVerilog.coreTitle(dp.name, cfg) + ",")

  /** One Embree figure and the conditions it was taken under: the 1-minute load average (/proc/loadavg) just before
    * the try that gave it (the machine is shared, so a high load understates Embree), when (UTC), and the host
    * ([[host]]: Embree's speed varies up to 2x from one host of these shared VMs to the next). */
  final case class Embree(
      packetsMrays: Double,
      singleMrays: Double,
      threads: Int,
      load1: Double = Double.NaN,
      at: String = "unknown",
      host: String = "unknown"
  )
  private val embreeRe =
    """Embree(?: ROBUST)? ([\d.]+) Mrays/s in packets of 8, ([\d.]+) Mrays/s one by one, on (\d+) threads""".r

  /** The 1-minute load average, or NaN where /proc/loadavg is missing. */
  def load1(): Double = {
    val f = Paths.get("/proc/loadavg")
    if (Files.exists(f)) Files.readString(f).trim.split(' ').head.toDouble else Double.NaN
  }

  /** The flags of /proc/cpuinfo that choose Embree's kernels (its SSE, AVX, AVX2 and AVX-512 paths). */
  val SimdFlags: Seq[String] = Seq("sse", "ssse3", "avx", "fma", "f16c", "bmi")

  /** This host as Embree sees it: /proc/cpuinfo's model name, its logical CPUs and its SIMD flags ([[SimdFlags]]);
    * "unknown" where /proc/cpuinfo is missing. */
  def host(cpuinfo: Path = Paths.get("/proc/cpuinfo")): String =
    if (!Files.exists(cpuinfo)) "unknown"
    else {
      val lines = Files.readAllLines(cpuinfo).asScala.toSeq
      def field(k: String) = lines.find(l => l.startsWith(k) && l.contains(':')).map(_.split(":", 2)(1).trim)
      val flags = field("flags").toSeq.flatMap(_.split(' ')).filter(f => SimdFlags.exists(f.startsWith)).distinct.sorted
      s"${field("model name").getOrElse("unknown model")}, ${lines.count(_.startsWith("processor"))} CPUs, SIMD flags ${flags.mkString(" ")}"
    }

  def utcNow(): String = java.time.Instant.now().truncatedTo(java.time.temporal.ChronoUnit.SECONDS).toString

  /** `nori-bridge bench` on a whole ray set: the best of `tries` (the machine is shared; others' load only slows it). */
  def embree(bridge: Path, pkg: Path, tries: Int = 3): Embree = (1 to tries).map { _ =>
    val (load, at) = (load1(), utcNow())
    val out = Process(Seq(bridge.toString, "bench", "--package", pkg.toString)).!!
    embreeRe.findFirstMatchIn(out).map(m =>
      Embree(m.group(1).toDouble, m.group(2).toDouble, m.group(3).toInt, load, at, host())
    )
      .getOrElse(throw new IllegalStateException(
        s"nori-bridge bench --package $pkg: no Embree figure in its output:\n$out"
      ))
  }.maxBy(_.packetsMrays)

  /** The package of `run` that the system rows simulate (its whole ray set): Embree runs on it too. */
  def packageDir(root: Path, layout: String, run: Bench.Run): Path = root.resolve(layout).resolve(run.name)

  /** Re-measures only Embree on the runs a cached result holds (`make bench-embree`): the packages are recompiled
    * (nori-bridge compile is deterministic), nothing is simulated. */
  def remeasureEmbree(a: Bench.Args, r: Result, root: Path): Result = {
    val runs = Bench.Runs.filter(run => r.embree.contains(run.name))
    r.copy(embree = runs.map { run =>
      val dir = packageDir(root, a.systemLayout, run)
      Bridge.compile(a.bridge, Paths.get(run.xml), dir, run.rays, bvh = Some(a.systemLayout))
      val e = embree(a.bridge, dir)
      println(
        f"bench: ${run.name}: Embree ${e.packetsMrays}%.2f Mrays/s (packets of 8, ${e.threads} threads, load ${e.load1}%.2f)"
      )
      run.name -> e
    }.toMap)
  }

  /** Where the system rows came from: the commit (`-dirty` if a tracked file outside docs/ and README.md, which do
    * not change what is measured, differed from it) and the time (UTC). */
  final case class Provenance(commit: String, at: String)

  def provenance(): Provenance = {
    def git(args: String*) = scala.util.Try(Process("git" +: args).!!.trim).toOption
    val head = git("rev-parse", "--short", "HEAD").getOrElse("unknown")
    val dirty = scala.util.Try(Process(Seq(
      "git",
      "diff",
      "--quiet",
      "HEAD",
      "--",
      ".",
      ":(exclude)docs",
      ":(exclude)README.md"
    )).! != 0)
      .getOrElse(false)
    Provenance(head + (if (dirty) "-dirty" else ""), utcNow())
  }

  /** What rtaccel-sim reads (image.bin, rays.csv) for `rays`, renumbered 0..n-1 in order (rtaccel-sim's rule). */
  def subsetPackage(pkg: ScenePackage, rays: IndexedSeq[RayRecord], dir: Path): Path = {
    Files.createDirectories(dir)
    Files.copy(pkg.dir.resolve("image.bin"), dir.resolve("image.bin"), StandardCopyOption.REPLACE_EXISTING)
    val lines = Files.readAllLines(pkg.dir.resolve("rays.csv")).asScala.toIndexedSeq
    val body = rays.zipWithIndex.map { case (r, i) =>
      val l = lines(r.number.toInt + 1) // rays.csv: a header, then ray k on line k + 2 (index k + 1)
      require(l.startsWith(s"${r.number},"), s"${pkg.dir}/rays.csv: line ${r.number + 2} is not ray ${r.number}: '$l'")
      s"$i${l.substring(l.indexOf(','))}"
    }
    Files.write(dir.resolve("rays.csv"), (lines.head +: body).asJava)
    dir
  }

  /** The whole section's measurements: one row per (run, cores), simulated with the DDR model at `fabricMhz`
    * (the whole MHz of `verilog`'s Fmax estimate) at `sim`, with the Embree speeds. `now` is what make verilog's
    * resources.md says when the section is redrawn from the cache, where it differs from `verilog`: the estimate
    * then takes its cores and Fmax, and the markdown says so. */
  final case class Result(
      rows: Seq[ujson.Obj],
      embree: Map[String, Embree],
      verilog: VerilogFigures,
      fabricMhz: Int,
      sim: Provenance = Provenance("unknown", "unknown"),
      now: Option[(VerilogFigures, Provenance)] = None,
      layout: String = DefaultLayout,
      boxTest: String = rtaccel.BoxTest.Fp32.name
  ) {

    /** The figures the estimate uses: the redrawn ones if any, else those of the simulation. */
    def estimateFigures: VerilogFigures = now.fold(verilog)(_._1)

    /** The clock of the estimate, whole MHz rounded down (as the simulation's DDR model clock). */
    def estimateMhz: Int = BenchSystem.wholeMhz(estimateFigures)
  }

  /** What `make verilog` wrote in `verilog` for the default system (4-wide FP32 cores), refused if it was made for
    * another configuration. */
  def defaultFigures(verilog: Path): VerilogFigures = {
    val (a, dp) = (Bench.Args(verilog = verilog), Bench.datapath)
    figures(verilog, dp, config(a, dp))
  }

  /** What `make verilog` wrote in `verilog`, refused unless it was made for the system the bench builds: cores
    * of `cfg`, the node store SystemConfig gives (NODE_STORE_KIB). */
  private def figures(verilog: Path, dp: FloatDatapath, cfg: AccelConfig): VerilogFigures =
    VerilogFigures.read(verilog, expectTitle(dp, cfg), Some(rtaccel.system.SystemConfig.defaultNodeStoreBytes / 1024))

  /** Whole MHz, rounded down, so the DDR latency in cycles is never understated by a fraction, and at most the
    * MIG's user-interface clock, which the system runs on (no clock crossing): a faster estimate is margin, not
    * speed. */
  def wholeMhz(v: VerilogFigures): Int =
    math.floor(v.fmaxMhz.min(BenchSystemMarkdown.ClockCeilingMhz)).toInt.max(1)

  private def verilogJson(v: VerilogFigures) =
    ujson.Obj("title" -> v.title, "coresFit" -> v.coresFit, "fmaxNs" -> v.fmaxNs, "slowestUnit" -> v.slowestUnit)
  private def verilogOf(v: ujson.Value) =
    VerilogFigures(v("title").str, v("coresFit").num.toInt, v("fmaxNs").num, v("slowestUnit").str)
  private def nanOr(x: Double): ujson.Value = if (x.isNaN) ujson.Null else ujson.Num(x)

  /** The cache (build/bench/system.json) holds what was simulated; `now` is never stored (re-read at each redraw). */
  def toJson(r: Result): ujson.Obj = ujson.Obj(
    "rows" -> ujson.Arr(r.rows: _*),
    "fabricMhz" -> r.fabricMhz,
    "layout" -> r.layout,
    "boxTest" -> r.boxTest,
    "commit" -> r.sim.commit,
    "at" -> r.sim.at,
    "verilog" -> verilogJson(r.verilog),
    "embree" -> ujson.Obj.from(r.embree.map { case (k, e) =>
      k -> ujson.Obj(
        "packetsMrays" -> e.packetsMrays,
        "singleMrays" -> e.singleMrays,
        "threads" -> e.threads,
        "load1" -> nanOr(e.load1),
        "at" -> e.at,
        "host" -> e.host
      )
    })
  )

  /** Reads the cache; a cache written before the load average and commit were recorded reads them as unknown. */
  def fromJson(j: ujson.Value): Result = {
    def str(o: ujson.Value, k: String) = o.obj.get(k).map(_.str).getOrElse("unknown")
    Result(
      j("rows").arr.map(x => ujson.Obj.from(x.obj)).toSeq,
      j("embree").obj.map { case (k, e) =>
        k -> Embree(
          e("packetsMrays").num,
          e("singleMrays").num,
          e("threads").num.toInt,
          e.obj.get("load1").flatMap(_.numOpt).getOrElse(Double.NaN),
          str(e, "at"),
          str(e, "host")
        )
      }.toMap,
      verilogOf(j("verilog")),
      j("fabricMhz").num.toInt,
      Provenance(str(j, "commit"), str(j, "at")),
      layout = j.obj.get("layout").fold(DefaultLayout)(_.str),
      boxTest = j.obj.get("boxTest").fold(rtaccel.BoxTest.Fp32.name)(_.str)
    )
  }

  /** A cached result redrawn against what resources.md says now (make verilog may have run since). */
  def redraw(a: Bench.Args, dp: FloatDatapath, r: Result): Result = {
    if (r.layout != a.systemLayout || r.boxTest != a.boxTest.name)
      throw new IllegalArgumentException(
        s"${cacheFile(a)} holds a system of ${r.layout} nodes with ${r.boxTest} box tests, " +
          s"not ${a.systemLayout} with ${a.boxTest.name}: run `make bench` (BENCH_SYSTEM=1) with the same BVH= and BOX_TEST="
      )
    val v = figures(a.verilog, dp, config(a, dp))
    val cores = r.rows.map(_("cores").num.toInt).distinct.sorted
    if (!cores.contains(v.coresFit))
      throw new IllegalArgumentException(
        s"${a.verilog}: ${v.coresFit} cores fit now, but ${cacheFile(a)} " +
          s"(simulated at ${r.sim.commit}) holds rows for ${cores.mkString(", ")} cores only: run `make bench` (BENCH_SYSTEM=1)"
      )
    if (v == r.verilog) r
    else {
      val written = java.time.Instant.ofEpochMilli(Files.getLastModifiedTime(a.verilog).toMillis)
        .truncatedTo(java.time.temporal.ChronoUnit.SECONDS).toString
      r.copy(now = Some(v -> Provenance(provenance().commit, written)))
    }
  }

  def run(a: Bench.Args, dp: FloatDatapath, golden: rtaccel.datapath.FloatGolden, root: Path): Result = {
    val cfg = config(a, dp)
    val v = figures(a.verilog, dp, cfg)
    // The DDR model's clock is the accelerator's: ns -> cycles and 12.8 GB/s -> bytes per cycle at the estimated Fmax
    // (whole MHz, rounded down, so the latency in cycles is never understated by a fraction).
    val mhz = wholeMhz(v)
    val sim = provenance()
    val cores = (Cores :+ v.coresFit).distinct.sorted
    println(
      s"bench: system: ${v.coresFit} cores fit, Fmax estimate ${"%.1f".format(v.fmaxMhz)} MHz (${v.slowestUnit}); " +
        s"simulating ${cores.mkString(", ")} cores at $mhz MHz"
    )
    val packages = a.runs.map { run =>
      val x = prepare(a, cfg, golden, root, run)
      val e = embree(a.bridge, packageDir(root, a.systemLayout, run))
      println(
        f"bench: ${run.name}: Embree ${e.packetsMrays}%.2f Mrays/s (packets of 8, ${e.threads} threads, load ${e.load1}%.2f)"
      )
      (x, e)
    }
    val rows = for (n <- cores; dir = CppSim.build(cfg, dp, n); (x, _) <- packages)
      yield simulate(x, n, dir, mhz, root.resolve("system").resolve(s"${x.run.name}-c$n"))
    Result(
      rows,
      packages.map { case (x, e) => x.run.name -> e }.toMap,
      v,
      mhz,
      sim,
      layout = cfg.layout.name,
      boxTest = cfg.boxTest.name
    )
  }

  /** A ray set ready to simulate: its package, the sample simulated, the golden model's hits for it (by ray number)
    * and the subset package rtaccel-sim reads. */
  final case class Prepared(
      run: Bench.Run,
      p: ScenePackage,
      rays: IndexedSeq[RayRecord],
      golden: Map[Long, HitRecord],
      sub: Path
  )

  def prepare(
      a: Bench.Args,
      cfg: AccelConfig,
      golden: rtaccel.datapath.FloatGolden,
      root: Path,
      run: Bench.Run
  ): Prepared = {
    val layout = cfg.layout.name
    val dir = packageDir(root, layout, run)
    Bridge.compile(a.bridge, Paths.get(run.xml), dir, run.rays, bvh = Some(layout))
    val p = ScenePackage.load(dir)
    require(p.misfits(cfg).isEmpty, s"${run.name} ($layout): ${p.misfits(cfg).mkString("; ")}")
    val rays = SpeedRuns.sample(p.rays, a.maxRays)
    val g = GoldenHits.run(cfg, p.image, golden, rays, a.threads).hits.map(h => h.number -> h).toMap
    Prepared(run, p, rays, g, subsetPackage(p, rays, root.resolve("system").resolve(s"${run.name}-${rays.size}")))
  }

  /** One row: `x` through the simulator built in `dir` (`cores` cores) with the DDR model at `mhz`, every hit
    * checked against the golden model (a mismatch fails). */
  def simulate(x: Prepared, cores: Int, dir: Path, mhz: Int, out: Path): ujson.Obj = {
    val Prepared(run, p, rays, g, sub) = x
    val n = cores
    Files.createDirectories(out)
    val args = RegressArgs(sub, out, fabricMhz = mhz.toDouble)
    val (r, speed) = CppSim.run(args, dir, p.image.nodeBytes.toInt, rays.size)
    // Hit i answers the subset's ray i: give it the set's number back before the golden check.
    val hits: Seq[HitRecord] = r.hits.zipWithIndex.map { case (h, i) => h.copy(number = rays(i).number) }
    val bad = SweepPoint.sameAnswers(rays.map(x => x.number -> x).toMap, hits, g)
    require(bad == 0, s"${run.name}, $n cores: $bad of ${rays.size} rays differ from the golden model")
    def perf(k: String) = r.perf.getOrElse(k, BigInt(0)).toDouble
    val storeReads = perf("nodeStoreHits") + perf("nodeStoreMisses")
    // m_axi's R beats in the batch (the DDR model's count), of the m_axi width each, at most one per cycle.
    val simMem = ujson.read(Files.readString(out.resolve("sim-memory.json")))
    val axi = simMem("axi")
    // DRAM bytes per ray by the image region they touched (whole 64-byte bursts, the DDR model's charge).
    val regions = ujson.Obj.from(simMem.obj.get("regions").toSeq.flatMap(_.obj).map { case (k, v) =>
      k -> ujson.Num((v("readBytes").num + v("writeBytes").num) / rays.size)
    })
    val readBeats = axi("readBeats").num
    val beatBytes = axi("beatBytes").num
    val row = ujson.Obj(
      "run" -> run.name,
      "cores" -> n,
      "rayIds" -> args.numRayIds,
      "rays" -> rays.size,
      "raySetSize" -> p.rays.size,
      "cycles" -> r.cycles.toDouble,
      "raysPerCycle" -> rays.size.toDouble / r.cycles,
      "nodeStoreHitRate" -> (if (storeReads > 0) perf("nodeStoreHits") / storeReads else 0.0),
      "dramBytesPerRay" -> r.dram.fold(0.0)(_.bytes.toDouble / rays.size),
      "readBytesPerRay" -> beatBytes * readBeats / rays.size,
      "readBeatsPerCycle" -> readBeats / r.cycles,
      "axiDataBits" -> 8 * beatBytes,
      "dramBusy" -> r.dram.fold(0.0)(_.busyCycles.toDouble / r.cycles),
      "goldenMismatches" -> bad,
      "dramRegionBytesPerRay" -> regions,
      "simCyclesPerSecond" -> speed("cyclesPerSecond").num,
      "simCyclesPerCpuSecond" -> speed("cyclesPerCpuSecond").num
    )
    println(f"bench: system ${run.name}%-20s $n cores ${8 * beatBytes}%.0f-bit m_axi ${rays.size}%5d rays ${r.cycles}%,9d cycles " +
      f"${rays.size.toDouble / r.cycles}%.4f r/c")
    row
  }
}
