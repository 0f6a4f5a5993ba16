package rtaccel.tools

import chisel3._
import rtaccel.fp._

import java.nio.file.{Files, Path, Paths}
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._

/** `make fp-area`: emits each floating-point unit at its default latency for
  * several formats, synthesises each one alone with Yosys
  * (`synth_xilinx -family xc7`), and writes the LUT/FF/SRL/DSP/CARRY4 counts
  * and latencies to a Markdown table.
  *
  * Usage: FpAreaReport <build dir> <output .md> [parallel jobs]
  */
object FpAreaReport {
  private val firtoolOpts = Array(
    "--lowering-options=disallowLocalVariables,disallowPackedArrays",
    "-disable-all-randomization", "-strip-debug-info")

  /** One unit to synthesise: table label, latency, and its generator. */
  final case class AreaUnit(fmt: FloatFormat, label: String, latency: Int, gen: () => RawModule)

  def units(fmt: FloatFormat): Seq[AreaUnit] = {
    val rne = Some(RoundingMode.RNE)
    val f32 = FloatFormat.FP32
    val base = Seq(
      AreaUnit(fmt, "add (RNE)", FpAdd.defaultLatency, () => new FpAdd(fmt, rne)),
      AreaUnit(fmt, "mul (RNE)", FpMul.defaultLatency, () => new FpMul(fmt, rne)),
      AreaUnit(fmt, "div (RNE)", FpDivCore.defaultLatency(fmt), () => new FpDiv(fmt, rne)),
      AreaUnit(fmt, "recip (RNE)", FpDivCore.defaultLatency(fmt), () => new FpRecip(fmt, rne)),
      AreaUnit(fmt, "compare/min/max", FpCompare.defaultLatency, () => new FpCompare(fmt)),
      AreaUnit(fmt, "add (runtime rm)", FpAdd.defaultLatency, () => new FpAdd(fmt, None))
    )
    val conv =
      if (fmt == f32) Nil
      else Seq(AreaUnit(fmt, s"convert e8m23 -> $fmt (RDN)", FpConvert.defaultLatency, () => new FpConvert(f32, fmt, Some(RoundingMode.RDN))))
    base ++ conv
  }

  final case class Area(lut: Int, ff: Int, srl: Int, dsp: Int, carry: Int)

  /** Sums the cell counts of the flattened top's `stat` block. */
  def parseStat(log: String, file: Path): Area = {
    val cells = """(?m)^\s+(\w+)\s+(\d+)\s*$""".r
    val block = log.lastIndexOf("Number of cells:")
    require(block >= 0, s"$file: no 'Number of cells' in the Yosys log")
    val counts = cells.findAllMatchIn(log.substring(block)).map(m => m.group(1) -> m.group(2).toInt).toSeq
    def sum(p: String => Boolean) = counts.collect { case (c, n) if p(c) => n }.sum
    Area(lut = sum(_.matches("LUT[1-6].*")), ff = sum(_.matches("FD[A-Z_0-9]*")),
      srl = sum(_.startsWith("SRL")), dsp = sum(_.startsWith("DSP48")), carry = sum(_ == "CARRY4"))
  }

  def main(args: Array[String]): Unit = {
    require(args.length >= 2, "usage: FpAreaReport <build dir> <output .md> [jobs]")
    val dir = Paths.get(args(0))
    val out = Paths.get(args(1))
    val jobs = if (args.length > 2) args(2).toInt else 2
    Files.createDirectories(dir)
    val formats = Seq(FloatFormat.FP32, FloatFormat(8, 15), FloatFormat(8, 10), FloatFormat(8, 7), FloatFormat(6, 9))
    val todo = formats.flatMap(units)
    // Elaborate serially (Chisel is not re-entrant-safe here); run Yosys in parallel.
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    val t0 = System.nanoTime()
    val emitted = todo.map { u =>
      val sv = _root_.circt.stage.ChiselStage.emitSystemVerilog(u.gen(), firtoolOpts = firtoolOpts)
      (u, sv)
    }
    val results = emitted.map { case (u, sv) =>
      Future {
        val top = """(?m)^module (\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq.last
        val svFile = dir.resolve(s"$top.sv")
        Files.writeString(svFile, sv)
        val logFile = dir.resolve(s"$top.yosys.log")
        val rc = Seq("yosys", "-q", "-l", logFile.toString, "-p",
          s"read_verilog -sv $svFile; synth_xilinx -family xc7 -top $top; stat").!(ProcessLogger(_ => ()))
        require(rc == 0, s"yosys failed on $svFile (exit $rc); see $logFile")
        val area = parseStat(Files.readString(logFile), logFile)
        println(s"fp-area: $top: $area")
        (u, top, area)
      }
    }
    val rows = results.map(Await.result(_, Duration.Inf))
    pool.shutdown()
    Files.createDirectories(out.toAbsolutePath.getParent)
    Files.writeString(out, FpAreaMarkdown(rows, (System.nanoTime() - t0) / 1e9))
    println(s"fp-area: wrote $out")
  }
}
