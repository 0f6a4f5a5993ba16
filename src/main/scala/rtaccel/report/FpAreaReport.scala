package rtaccel.report

import chisel3._
import rtaccel.fp._
import rtaccel.tools.Synth

import java.nio.file.{Files, Path, Paths}
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}

/** `make fp-area`: emits each floating-point unit at its default latency for
  * several formats, synthesises each one alone with Yosys
  * (`synth_xilinx -family xc7`), and writes the LUT/FF/SRL/DSP/CARRY4 counts
  * and latencies to a Markdown table.
  *
  * Usage: FpAreaReport <build dir> <output .md> [parallel jobs]
  */
object FpAreaReport {

  /** One unit to synthesise: table label, latency, and its generator. */
  final case class AreaUnit(fmt: FloatFormat, label: String, latency: Int, gen: () => RawModule)

  def units(fmt: FloatFormat): Seq[AreaUnit] = {
    val rne = Some(RoundingMode.RNE)
    val f32 = FloatFormat.FP32
    val base = Seq(
      AreaUnit(fmt, "add (RNE)", FpAdd.defaultLatency, () => new FpAdd(fmt, rne)),
      AreaUnit(fmt, "mul (RNE)", FpMul.defaultLatency, () => new FpMul(fmt, rne)),
      AreaUnit(fmt, "div (RNE)", FpDivCore.defaultLatency(fmt), () => new FpDiv(fmt, rne)),
      AreaUnit(fmt, "recip (RNE)", FpRecipCore.defaultLatency(fmt), () => new FpRecip(fmt, rne)),
      AreaUnit(fmt, "compare/min/max", FpCompare.defaultLatency, () => new FpCompare(fmt)),
      AreaUnit(fmt, "add (runtime rm)", FpAdd.defaultLatency, () => new FpAdd(fmt, None))
    )
    val conv =
      if (fmt == f32) Nil
      else Seq(AreaUnit(
        fmt,
        s"convert e8m23 -> $fmt (RDN)",
        FpConvert.defaultLatency,
        () => new FpConvert(f32, fmt, Some(RoundingMode.RDN))
      ))
    base ++ conv
  }

  type Area = Synth.Area

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
      val sv = Synth.emit(u.gen())
      (u, sv)
    }
    val results = emitted.map { case (u, sv) =>
      Future {
        val top = """(?m)^module (\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq.last
        val svFile = dir.resolve(s"$top.sv")
        Files.writeString(svFile, sv)
        val area = Synth.yosys(svFile, top)
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
