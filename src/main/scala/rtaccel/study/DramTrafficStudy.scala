package rtaccel.study

import rtaccel.AccelConfig
import rtaccel.bench.BenchSystem
import rtaccel.bvh.BvhLayout
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.scene.ScenePackage

import java.nio.file.{Files, Path, Paths}
import scala.collection.mutable

/** `make dram-traffic-study`: DRAM bytes per ray of the candidate memory designs (Candidates) on paper, from the
  * golden walk's reads, counted in whole 64-byte lines as the system's DDR model charges them, and the bound each
  * gives in Mrays/s on the ZC706 (an estimate: docs/dram-traffic.md). Reads packages compiled into
  * `<root>/<layout>/<run>` for every layout the candidates name; writes a markdown report.
  */
object DramTrafficStudy {
  final case class Args(
      root: Path = Paths.get("build/dram-traffic"),
      maxRays: Int = 2048,
      runs: Seq[String] = Seq("dragon-primary", "dragon-shadow", "dragon-ao"),
      out: Path = Paths.get("build/dram-traffic/study.md"),
      command: String = "make dram-traffic-study",
      /** Only the candidates whose name contains one of these (all when empty). */
      only: Seq[String] = Nil,
      /** m_axi's clock for the R channel's bound, MHz (default: [[clockOf]]). */
      clockMhz: Option[Double] = None,
      /** Block RAM of one core, BRAM36 (default: [[coreBramOf]]). */
      coreBram: Option[Double] = None,
      /** What `make verilog` wrote: the default system's Fmax estimate and the cores' block RAM. */
      verilog: Path = Paths.get("build/verilog/resources.md")
  )

  val usage = "usage: DramTrafficStudy [--root build/dram-traffic] [--max-rays 2048] [--runs dragon-primary,...] " +
    "[--out build/dram-traffic/study.md] [--only today,cache,...] [--clock-mhz 141] [--core-bram 43.5] " +
    "[--verilog build/verilog/resources.md]"

  def parse(args: Seq[String]): Args = {
    def fail(why: String): Nothing = throw new IllegalArgumentException(s"$why\n$usage")
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    args.grouped(2).map(p => p(0) -> p(1)).foldLeft(Args()) { case (a, (k, v)) =>
      k match {
        case "--root" => a.copy(root = Paths.get(v))
        case "--max-rays" =>
          a.copy(maxRays = v.toIntOption.filter(_ >= 1).getOrElse(fail(s"--max-rays: '$v' is not a whole number >= 1")))
        case "--runs" => a.copy(runs = v.split(',').map(_.trim).filter(_.nonEmpty).toSeq)
        case "--out"  => a.copy(out = Paths.get(v))
        case "--only" =>
          val keys = v.split(',').map(_.trim).filter(_.nonEmpty).toSeq
          keys.filterNot(k => Candidates.all.exists(_.key == k)).foreach(k =>
            fail(s"--only: '$k' is not one of ${Candidates.all.map(_.key).mkString(", ")}")
          )
          a.copy(only = keys)
        case "--clock-mhz" =>
          a.copy(clockMhz =
            Some(v.toDoubleOption.filter(_ > 0).getOrElse(fail(s"--clock-mhz: '$v' is not a clock in MHz > 0")))
          )
        case "--core-bram" =>
          a.copy(coreBram =
            Some(v.toDoubleOption.filter(_ >= 0).getOrElse(fail(s"--core-bram: '$v' is not a BRAM36 count >= 0")))
          )
        case "--verilog" => a.copy(verilog = Paths.get(v))
        case other       => fail(s"unknown option '$other'")
      }
    }
  }

  def main(args: Array[String]): Unit =
    try run(parse(args.toSeq), s"runMain rtaccel.study.DramTrafficStudy ${args.mkString(" ")}")
    catch { case e: IllegalArgumentException => System.err.println(s"Error: ${e.getMessage}"); sys.exit(2) }

  /** The ZC706's channels (docs/dram-traffic.md): PL DDR3 12.8 GB/s; PS DDR3 through the HP ports 4.3 GB/s. In
    * MB/s. m_axi's R channel carries one 64-byte beat per cycle of its clock (`PortRead`). */
  val PlDdr = 12800.0
  val PsDdr = 4300.0
  def PortRead(clockMhz: Double): Double = 64 * clockMhz

  /** The clock the R channel's bound assumes: `--clock-mhz`, or the default system's Fmax estimate that
    * `make verilog` wrote (docs/fmax.md; an estimate, not a board measurement), in whole MHz rounded down as
    * `make bench` clocks its DDR model. Read, never hard-coded: the estimate moves with the design. */
  def clockOf(a: Args): Double =
    a.clockMhz.getOrElse(BenchSystem.wholeMhz(BenchSystem.defaultFigures(a.verilog)).toDouble)

  /** The block RAM every core takes beside the stores: `--core-bram`, or what `make verilog` measured for the
    * default core (docs/fmax.md). The candidates' stores, caches and queues get what the cores leave. */
  def coreBramOf(a: Args): Double = a.coreBram.getOrElse(rtaccel.regress.VerilogFigures.coreBram36(a.verilog))

  /** BRAM36 of candidate `c` with `cores` cores: its stores and what it adds, and the cores' own. */
  def deviceBram(c: Candidate, cores: Int, batch: Int, coreBram: Double): Int =
    c.bram(cores, batch) + math.ceil(cores * coreBram).toInt

  /** `command`: how it was called, for the report's first line. */
  def run(a: Args, command: String): Unit = {
    val mhz = clockOf(a) // first: a missing or foreign resources.md fails before the walk
    val coreBram = coreBramOf(a)
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.parse("watertight"), BoxRounding.parse("conservative"))
    val golden = FloatGolden(dp)
    val md = new StringBuilder
    md ++= s"Generated by `$command` (`make dram-traffic-study` runs it on the packages it compiles); do not edit. " +
      "Method and reading: docs/dram-traffic.md.\n\n"
    md ++= s"DRAM bytes per ray, whole 64-byte lines, at 2 cores (${Traffic.IdsPerCore} ray IDs each): nodes / triangles / rays / hits (+ parked " +
      "ray states) = total; the total at 1 and 4 cores; BRAM36 at 1 / 2 / 4 cores: the stores, what the candidate adds " +
      f"and the cores' own ($coreBram%.1f per core, make verilog), in bold where past the xc7z045's 545; bounds in Mrays/s (estimates): the PL DDR3's 12.8 GB/s over the total, with the PS " +
      "DDR3's 4.3 GB/s beside it (best placement of whole regions: nodes, triangles, rays and hits), and m_axi's R " +
      f"channel (64 bytes per cycle at ${mhz}%.0f MHz, 512 bits) over the bytes read.\n"
    val packages = mutable.Map.empty[(String, String), (ScenePackage, IndexedSeq[RayReads])]
    def load(layout: String, run: String) = packages.getOrElseUpdate(
      (layout, run), {
        val p = ScenePackage.load(a.root.resolve(layout).resolve(run))
        val cfg = AccelConfig.zc706.copy(layout = BvhLayout.parse(layout))
        if (p.image.layout != cfg.layout)
          throw new IllegalArgumentException(s"${p.dir}: holds ${p.image.layout.name} nodes, not $layout")
        val t0 = System.nanoTime()
        val rays = RayReads.sample(p.rays, a.maxRays).map(RayReads.of(cfg, p.image, golden, _))
        println(f"dram-traffic: ${p.dir}: ${rays.size} rays walked in ${(System.nanoTime() - t0) / 1e9}%.1f s")
        (p, rays)
      }
    )
    for (run <- a.runs) {
      val (p0, rays0) = load("4", run)
      md ++= s"\n### $run (${rays0.size} of ${p0.rays.size} rays, strided)\n\n"
      md ++= "| candidate (key) | layout | BRAM36 1 / 2 / 4 cores | bytes/ray at 2 cores: nodes / triangles / rays / hits (+ parks) = total | " +
        f"total at 1 / 4 cores | parks/ray | bound, PL DDR 12.8 GB/s | PL + PS DDR | m_axi R at ${mhz}%.0f MHz |\n"
      md ++= "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: |\n"
      for (c <- Candidates.all if a.only.isEmpty || a.only.contains(c.key)) {
        val (p, rays) = load(c.layout, run)
        val t = Traffic.of(c, p.image, rays)
        def f0(x: Double) = f"$x%.0f"
        val bram = Traffic.Cores.map(k => deviceBram(c, k, rays.size, coreBram))
        val bramText = bram.map(b => if (b > MemoryDesign.DeviceBram36) s"**$b**" else b.toString).mkString(" / ")
        val parks = if (t.park > 0) s" + ${f0(t.park)}" else ""
        val split =
          s"${f0(t.nodes(1))} / ${f0(t.tris(1))} / ${f0(t.rays)} / ${f0(t.hits)}$parks = **${f0(t.total(1))}**"
        val row =
          s"| ${c.name} (`${c.key}`) | ${c.layout} | $bramText | $split | ${f0(t.total(0))} / ${f0(t.total(2))} | " +
            f"${t.parks}%.1f | ${PlDdr / t.total(1)}%.1f | ${withPs(t)}%.1f | ${PortRead(mhz) / t.readBytes(1)}%.1f |"
        md ++= row + "\n"
        println(s"$run $row")
      }
    }
    Files.createDirectories(a.out.toAbsolutePath.getParent)
    Files.writeString(a.out, md.toString)
    println(s"dram-traffic: wrote ${a.out}")
  }

  /** The bound with both DDR channels: each region (nodes, triangles, rays with hits, parked states) on the PL or
    * the PS DDR, the best of the 16 placements (min over channels of bandwidth over its bytes). */
  def withPs(t: Traffic): Double = {
    val regions = Seq(t.nodes(1), t.tris(1), t.rays + t.hits, t.park)
    (0 until (1 << regions.size)).map { m =>
      val ps = regions.indices.filter(i => (m >> i & 1) == 1).map(regions).sum
      val pl = regions.sum - ps
      (if (pl > 0) PlDdr / pl else Double.PositiveInfinity).min(if (ps > 0) PsDdr / ps else Double.PositiveInfinity)
    }.max
  }
}
