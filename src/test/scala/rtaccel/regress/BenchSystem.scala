package rtaccel.regress

import rtaccel.AccelConfig
import rtaccel.datapath.FloatDatapath
import rtaccel.golden.{HitRecord, RayRecord}
import rtaccel.scene.{MemoryImage, ScenePackage}
import rtaccel.sweep.{GoldenHits, SpeedRuns, SweepPoint}

import java.nio.file.{Files, Path, Paths, StandardCopyOption}
import scala.jdk.CollectionConverters._
import scala.sys.process._

/** `make bench`'s system section (issue 13, part 3): rays/cycle of the system
  * top (rtaccel_system: N cores, MemoryFabric and its node store, ray and hit
  * DMA, registers) under the C++ harness (sw/sim/, the DDR model behind
  * m_axi) for N = 1, 2, 4 and the cores that fit; every simulated ray checked
  * bit for bit against the golden model. The ZC706 estimate multiplies the
  * fitting system's rays/cycle by the Fmax estimate, both read from what
  * `make verilog` wrote (VerilogFigures); Embree runs on this machine on the
  * same ray sets (`nori-bridge bench`, 2 threads).
  */
object BenchSystem {
  /** The core every system row instantiates: the ZC706 configuration, 4-wide nodes (what make verilog builds by default). */
  val Layout = "4"
  /** Core counts always measured; the cores that fit are added. */
  val Cores: Seq[Int] = Seq(1, 2, 4)
  /** Words resources.md's title must hold for its figures to be this core's. */
  def expectTitle(dp: FloatDatapath, cfg: AccelConfig): Seq[String] =
    Seq(s"RtAccel ${dp.name},", s"(${cfg.boxLanes} box lanes)", s"${cfg.numRayIds} ray IDs")

  final case class Embree(packetsMrays: Double, singleMrays: Double, threads: Int)
  private val embreeRe = """Embree(?: ROBUST)? ([\d.]+) Mrays/s in packets of 8, ([\d.]+) Mrays/s one by one, on (\d+) threads""".r

  /** `nori-bridge bench` on a whole ray set: the best of `tries` (the machine is shared; others' load only slows it). */
  def embree(bridge: Path, pkg: Path, tries: Int = 3): Embree = (1 to tries).map { _ =>
    val out = Process(Seq(bridge.toString, "bench", "--package", pkg.toString)).!!
    embreeRe.findFirstMatchIn(out).map(m => Embree(m.group(1).toDouble, m.group(2).toDouble, m.group(3).toInt))
      .getOrElse(throw new IllegalStateException(s"nori-bridge bench --package $pkg: no Embree figure in its output:\n$out"))
  }.maxBy(_.packetsMrays)

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

  /** The whole section's measurements: one row per (run, cores), with the Embree speeds and make verilog's figures. */
  final case class Result(rows: Seq[ujson.Obj], embree: Map[String, Embree], verilog: VerilogFigures, fabricMhz: Int)

  def toJson(r: Result): ujson.Obj = ujson.Obj("rows" -> ujson.Arr(r.rows: _*), "fabricMhz" -> r.fabricMhz,
    "verilog" -> ujson.Obj("title" -> r.verilog.title, "coresFit" -> r.verilog.coresFit, "fmaxNs" -> r.verilog.fmaxNs,
      "slowestUnit" -> r.verilog.slowestUnit),
    "embree" -> ujson.Obj.from(r.embree.map { case (k, e) =>
      k -> ujson.Obj("packetsMrays" -> e.packetsMrays, "singleMrays" -> e.singleMrays, "threads" -> e.threads) }))

  def fromJson(j: ujson.Value): Result = {
    val v = j("verilog")
    Result(j("rows").arr.map(x => ujson.Obj.from(x.obj)).toSeq,
      j("embree").obj.map { case (k, e) => k -> Embree(e("packetsMrays").num, e("singleMrays").num, e("threads").num.toInt) }.toMap,
      VerilogFigures(v("title").str, v("coresFit").num.toInt, v("fmaxNs").num, v("slowestUnit").str), j("fabricMhz").num.toInt)
  }

  def run(a: Bench.Args, dp: FloatDatapath, golden: rtaccel.datapath.FloatGolden, root: Path): Result = {
    val cfg = Bench.configFor(Layout).copy(boxFloat = dp.boxFmt, triFloat = dp.triFmt)
    val v = VerilogFigures.read(a.verilog, expectTitle(dp, cfg))
    // The DDR model's clock is the accelerator's: ns -> cycles and 12.8 GB/s -> bytes per cycle at the estimated Fmax
    // (whole MHz, rounded down, so the latency in cycles is never understated by a fraction).
    val mhz = math.floor(v.fmaxMhz).toInt.max(1)
    val cores = (Cores :+ v.coresFit).distinct.sorted
    println(s"bench: system: ${v.coresFit} cores fit, Fmax estimate ${"%.1f".format(v.fmaxMhz)} MHz (${v.slowestUnit}); " +
      s"simulating ${cores.mkString(", ")} cores at $mhz MHz")
    val packages = a.runs.map { run =>
      val dir = root.resolve(Layout).resolve(run.name)
      Bridge.compile(a.bridge, Paths.get(run.xml), dir, run.rays, bvh = Some(Layout))
      val p = ScenePackage.load(dir)
      require(p.misfits(cfg).isEmpty, s"${run.name} ($Layout): ${p.misfits(cfg).mkString("; ")}")
      val rays = SpeedRuns.sample(p.rays, a.maxRays)
      val g = GoldenHits.run(cfg, p.image, golden, rays, a.threads).hits.map(h => h.number -> h).toMap
      val sub = subsetPackage(p, rays, root.resolve("system").resolve(s"${run.name}-${rays.size}"))
      val e = embree(a.bridge, dir)
      println(f"bench: ${run.name}: Embree ${e.packetsMrays}%.2f Mrays/s (packets of 8, ${e.threads} threads)")
      (run, p, rays, g, sub, e)
    }
    val rows = for (n <- cores; dir = CppSim.build(cfg, dp, n); (run, p, rays, g, sub, _) <- packages) yield {
      val out = root.resolve("system").resolve(s"${run.name}-c$n")
      Files.createDirectories(out)
      val args = RegressArgs(sub, out, fabricMhz = mhz.toDouble)
      val (r, speed) = CppSim.run(args, dir, p.image.nodeBytes.toInt, MemoryImage.TriBytes.toInt, rays.size)
      // Hit i answers the subset's ray i: give it the set's number back before the golden check.
      val hits: Seq[HitRecord] = r.hits.zipWithIndex.map { case (h, i) => h.copy(number = rays(i).number) }
      val bad = SweepPoint.sameAnswers(rays.map(x => x.number -> x).toMap, hits, g)
      require(bad == 0, s"${run.name}, $n cores: $bad of ${rays.size} rays differ from the golden model")
      def perf(k: String) = r.perf.getOrElse(k, BigInt(0)).toDouble
      val storeReads = perf("nodeStoreHits") + perf("nodeStoreMisses")
      // m_axi's R beats in the batch (the DDR model's count): 64 bytes each, at most one per cycle.
      val readBeats = ujson.read(Files.readString(out.resolve("sim-memory.json")))("axi")("readBeats").num
      val row = ujson.Obj("run" -> run.name, "cores" -> n, "rays" -> rays.size, "raySetSize" -> p.rays.size,
        "cycles" -> r.cycles.toDouble, "raysPerCycle" -> rays.size.toDouble / r.cycles,
        "nodeStoreHitRate" -> (if (storeReads > 0) perf("nodeStoreHits") / storeReads else 0.0),
        "dramBytesPerRay" -> r.dram.fold(0.0)(_.bytes.toDouble / rays.size), "readBytesPerRay" -> 64 * readBeats / rays.size,
        "readBeatsPerCycle" -> readBeats / r.cycles, "goldenMismatches" -> bad,
        "simCyclesPerSecond" -> speed("cyclesPerSecond").num, "simCyclesPerCpuSecond" -> speed("cyclesPerCpuSecond").num)
      println(f"bench: system ${run.name}%-20s $n cores ${rays.size}%5d rays ${r.cycles}%,9d cycles ${rays.size.toDouble / r.cycles}%.4f r/c")
      row
    }
    Result(rows, packages.map { case (run, _, _, _, _, e) => run.name -> e }.toMap, v, mhz)
  }
}
