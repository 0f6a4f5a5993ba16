package rtaccel.report

import rtaccel.datapath._
import chisel3._
import rtaccel.AccelConfig
import rtaccel.fetch.RayPrepUnit
import rtaccel.leaf.PrimIntersect
import rtaccel.traversal.{BoxLane, GridBboxIntersect}
import rtaccel.fp.FloatFormat
import rtaccel.tools.Synth

import java.nio.file.{Files, Path, Paths}
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}

/** First half of `make datapath-report`: emits each datapath unit alone and
  * synthesises it with Yosys (`synth_xilinx -family xc7`), one module per
  * run, appending `format variant unit latency lut ff srl dsp carry` rows to
  * `<dir>/area.tsv`. A unit whose Verilog is unchanged and whose Yosys log
  * already holds a `stat` block is not synthesised again (a rerun after an
  * interruption resumes).
  *
  * Usage: DatapathArea <build dir> [parallel jobs]
  */
object DatapathArea {
  final case class Job(fmt: FloatFormat, variant: String, unit: String, gen: () => RawModule)

  /** Every unit that differs: the box does not depend on the triangle test, nor the triangle on the box rounding. */
  def jobs(fmt: FloatFormat): Seq[Job] = {
    val cfg = AccelConfig().withFloat(fmt)
    def dp(t: TriangleTest, r: BoxRounding) = FloatDatapath(fmt, t, r)
    Seq(
      Job(fmt, "rne", "BoxLane", () => dp(TriangleTest.Moller, BoxRounding.Nearest).box(cfg)),
      Job(fmt, "cons", "BoxLane", () => dp(TriangleTest.Moller, BoxRounding.Conservative).box(cfg)),
      Job(fmt, "mt", "PrimIntersect", () => dp(TriangleTest.Moller, BoxRounding.Nearest).prim(cfg)),
      Job(fmt, "wt", "PrimIntersect", () => dp(TriangleTest.Watertight, BoxRounding.Nearest).prim(cfg)),
      Job(fmt, "mt_rne", "RayPrep", () => dp(TriangleTest.Moller, BoxRounding.Nearest).rayPrep(cfg)),
      Job(fmt, "wt_cons", "RayPrep", () => dp(TriangleTest.Watertight, BoxRounding.Conservative).rayPrep(cfg))
    )
  }
  val formats: Seq[FloatFormat] = Seq(FloatFormat.FP32, FloatFormat(8, 15), FloatFormat(8, 10), FloatFormat(6, 9))

  def main(args: Array[String]): Unit = {
    require(args.nonEmpty, "usage: DatapathArea <build dir> [jobs]")
    val dir = Paths.get(args(0))
    val pool = java.util.concurrent.Executors.newFixedThreadPool(if (args.length > 1) args(1).toInt else 2)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    Files.createDirectories(dir)
    // Elaborate serially; Yosys runs in parallel.
    val futures = formats.flatMap(jobs).map { j =>
      var unit: RawModule = null
      val sv = Synth.emit({ unit = j.gen(); unit })
      val latency = latencyOf(unit)
      val top = Synth.modules(sv).last
      Future(row(dir, j, top, sv, latency))
    }
    val rows = futures.map(Await.result(_, Duration.Inf))
    pool.shutdown()
    Files.writeString(dir.resolve("area.tsv"), rows.mkString("", "\n", "\n"))
    println(s"datapath-area: wrote ${dir.resolve("area.tsv")}")
  }

  /** The unit's derived latency, read from the elaborated module. */
  def latencyOf(m: RawModule): Int = m match {
    case b: BoxLane[_]        => b.latency
    case p: PrimIntersect[_]  => p.latency
    case r: RayPrepUnit[_]    => r.latency
    case g: GridBboxIntersect => g.latency
    case other                => throw new IllegalArgumentException(s"not a datapath unit: ${other.name}")
  }

  private def row(dir: Path, j: Job, top: String, sv: String, latency: Int): String = {
    val svFile = dir.resolve(s"$top.sv")
    val logFile = dir.resolve(s"$top.yosys.log")
    // Reuse a finished run only for the very same Verilog (a changed kernel resynthesises).
    val done = Files.exists(logFile) && Files.readString(logFile).contains("Number of cells:") &&
      Files.exists(svFile) && Files.readString(svFile) == sv
    val a =
      if (done) Synth.parseTotal(Files.readString(logFile), logFile)
      else { Files.writeString(svFile, sv); Synth.yosys(svFile, top) }
    println(s"datapath-area: $top: $a")
    Seq(j.fmt.name, j.variant, j.unit, latency, a.lut, a.ff, a.srl, a.dsp, a.carry).mkString("\t")
  }
}
