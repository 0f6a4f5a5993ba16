package rtaccel.bench

import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.system.SystemConfig
import rtaccel.regress.{Cli, CppSim, RegressArgs}

import java.nio.file.{Files, Path, Paths}

/** `make bench-wide`: the system section's rays (BenchSystem: Cornell and dragon camera rays, dragon shadow and AO;
  * at most `--max-rays` of each, every one checked bit for bit against the golden model) under the C++ harness for
  * each m_axi width of `--widths` (SystemConfig.axiDataBits) and each core count of `--cores`, with the ZC706 DDR
  * model clocked at `--mhz` (docs/reports/performance.md's estimate clock). Rows to build/bench/system-wide.json, a table to
  * build/bench/system-wide.md. A benchmark: simulated cycles, nothing timed.
  */
object BenchWide {
  final case class Args(
      widths: Seq[Int] = SystemConfig.AxiDataBitsChoices,
      cores: Seq[Int] = BenchSystem.Cores,
      mhz: Int = 100,
      maxRays: Int = 2048,
      runs: Seq[Bench.Run] = BenchWide.Runs,
      out: Path = Paths.get("build/bench/system-wide.md")
  )

  /** make bench's ray sets and the Cornell box's shadow and AO rays (records of the triangle store's scene). */
  val Runs: Seq[Bench.Run] =
    Bench.Runs ++ Seq("shadow", "ao").map(k => Bench.Run("cornell-box", "scenes/cornell-box/cornell-box.xml", k))

  def parse(args: Seq[String]): Args = {
    def fail(why: String): Nothing = throw new IllegalArgumentException(
      s"$why\nusage: BenchWide [--widths 512,1024] [--cores 1,2,4] [--mhz 100] [--max-rays 2048] [--runs a,b] [--out F.md]"
    )
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    args.grouped(2).map(p => p(0) -> p(1)).foldLeft(Args()) { case (a, (k, v)) =>
      def ints = v.split(',').map(_.trim).filter(_.nonEmpty).toSeq.map(x =>
        x.toIntOption.filter(_ >= 1)
          .getOrElse(fail(s"$k: '$x' is not a whole number >= 1"))
      )
      def one = ints match { case Seq(x) => x; case _ => fail(s"$k: '$v' is not one whole number") }
      k match {
        case "--widths"   => a.copy(widths = ints.map(w => SystemConfig.axiDataBitsOf(Some(w.toString))))
        case "--cores"    => a.copy(cores = ints)
        case "--mhz"      => a.copy(mhz = one)
        case "--max-rays" => a.copy(maxRays = one)
        case "--runs" => a.copy(runs =
            v.split(',').toSeq.map(n =>
              Runs.find(_.name == n)
                .getOrElse(fail(s"--runs: '$n' is not one of ${Runs.map(_.name).mkString(", ")}"))
            )
          )
        case "--out" => a.copy(out = Paths.get(v))
        case other   => fail(s"unknown option '$other'")
      }
    }
  }

  def main(args: Array[String]): Unit = Cli.orExit(run(parse(args.toSeq)))

  def run(a: Args): Unit = {
    val t0 = System.nanoTime()
    val root = Bench.root
    val base = RegressArgs(root, root)
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.parse(base.triangle), BoxRounding.parse(base.rounding))
    val cfg = Bench.configFor(BenchSystem.DefaultLayout).copy(boxFloat = dp.boxFmt, triFloat = dp.triFmt)
    val ba = Bench.Args(runs = a.runs, maxRays = a.maxRays)
    val prepared = a.runs.map(run => BenchSystem.prepare(ba, cfg, FloatGolden(dp), root, run))
    val sim = BenchSystem.provenance()
    val rows = for (w <- a.widths; n <- a.cores; dir = CppSim.build(cfg, dp, n, axiDataBits = w); x <- prepared)
      yield BenchSystem.simulate(x, n, dir, a.mhz, root.resolve("system-wide").resolve(s"${x.run.name}-w$w-c$n"))
    val secs = (System.nanoTime() - t0) / 1e9
    val json = ujson.Obj(
      "rows" -> ujson.Arr(rows: _*),
      "fabricMhz" -> a.mhz,
      "commit" -> sim.commit,
      "at" -> sim.at,
      "seconds" -> secs
    )
    Files.createDirectories(a.out.toAbsolutePath.getParent)
    Files.writeString(
      a.out.resolveSibling(a.out.getFileName.toString.stripSuffix(".md") + ".json"),
      ujson.write(json, indent = 2)
    )
    val md = markdown(rows, a, sim, secs)
    Files.writeString(a.out, md)
    println(md)
  }

  def markdown(rows: Seq[ujson.Obj], a: Args, sim: BenchSystem.Provenance, secs: Double): String = {
    def cell(run: String, w: Int, n: Int)(f: ujson.Obj => String) =
      rows.find(r => r("run").str == run && r("axiDataBits").num.toInt == w && r("cores").num.toInt == n).fold("-")(f)
    val head =
      s"| rays | m_axi | ${a.cores.map(n => s"$n ${if (n == 1) "core" else "cores"}: rays/cycle").mkString(" | ")} | " +
        a.cores.map(n => s"R beats/cycle ($n; max 1)").mkString(" | ") + " | " + a.cores.map(n =>
          s"DDR busy ($n)"
        ).mkString(" | ") +
        s" | DRAM bytes/ray (${a.cores.last}) | m_axi R bytes/ray (${a.cores.last}) | golden mismatches |"
    val sep = "| --- | --- |" + " ---: |" * (3 * a.cores.size + 3)
    val body = for (run <- a.runs.map(_.name); w <- a.widths) yield {
      val rc = a.cores.map(n => cell(run, w, n)(r => f"${r("raysPerCycle").num}%.4f"))
      val beats = a.cores.map(n => cell(run, w, n)(r => f"${r("readBeatsPerCycle").num}%.2f"))
      val busy = a.cores.map(n => cell(run, w, n)(r => f"${r("dramBusy").num}%.2f"))
      val last = a.cores.last
      val bytes = cell(run, w, last)(r => f"${r("dramBytesPerRay").num}%.0f")
      val rbytes = cell(run, w, last)(r => f"${r("readBytesPerRay").num}%.0f")
      val bad = rows.filter(r => r("run").str == run && r("axiDataBits").num.toInt == w).map(_(
        "goldenMismatches"
      ).num.toInt).sum
      s"| $run | $w-bit | ${(rc ++ beats ++ busy).mkString(" | ")} | $bytes | $rbytes | $bad |"
    }
    s"Simulated by `make bench-wide` at commit ${sim.commit} (${sim.at}, ${secs.round} s): the system top, 4-wide FP32 " +
      s"watertight cores (conservative boxes, ${rtaccel.AccelConfig.zc706.numRayIds} ray IDs each), under the C++ harness with the ZC706 DDR model behind m_axi " +
      s"(12.8 GB/s, 64-byte bursts, 100 ns latency, 64 outstanding, out of order) at ${a.mhz} MHz " +
      s"(${12800 / a.mhz} B/cycle of DDR). At most ${a.maxRays} rays per set, strided, each checked bit for bit against " +
      "the golden model. rays/cycle: of the whole system. R beats/cycle: m_axi read beats per cycle (64 bytes each at " +
      "512 bits, 128 at 1024). DDR busy: the share of cycles the DDR model's channel moved data.\n\n" +
      (head +: sep +: body).mkString("\n") + "\n" + regionTable(rows, a)
  }

  /** DRAM bytes per ray by image region, at 2 cores (the cores that fit) or the most cores run. */
  def regionTable(rows: Seq[ujson.Obj], a: Args): String = {
    val n = if (a.cores.contains(2)) 2 else a.cores.last
    val regions = Seq("nodes", "triangles", "rays", "hits")
    val body = for (
      run <- a.runs.map(_.name); w <- a.widths;
      r <- rows.find(r => r("run").str == run && r("axiDataBits").num.toInt == w && r("cores").num.toInt == n)
    ) yield {
      val per = r.obj.get("dramRegionBytesPerRay").map(_.obj).getOrElse(collection.mutable.LinkedHashMap.empty[
        String,
        ujson.Value
      ])
      s"| $run | $w | ${regions.map(g => per.get(g).fold("-")(v => f"${v.num}%.0f")).mkString(" | ")} | " +
        f"${r("dramBytesPerRay").num}%.0f | ${r("readBytesPerRay").num / (w / 8)}%.2f |"
    }
    s"\nWhat the DDR spends per ray ($n ${if (n == 1) "core" else "cores"}, bytes of whole 64-byte bursts, from `sim-memory.json`'s regions):\n\n" +
      "| rays | m_axi | nodes | triangles | rays | hits | DRAM bytes/ray | R beats/ray |\n| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |\n" +
      body.mkString("\n") + "\n"
  }
}
