package rtaccel.tools

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.scene.ScenePackage
import rtaccel.{AccelConfig, RtAccel}

import java.nio.file.{Files, Path, Paths}
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._

/** `make verilog`: the accelerator's SystemVerilog for the ZC706 (xc7z045),
  * lint under `verilator --lint-only -Wall` (waivers with reasons in
  * verilator-waivers.vlt), and a Yosys resource table per unit and in total
  * beside the device's capacity. Each unit is synthesized on its own (a
  * flattened run of the whole FP-heavy design takes far longer) and the
  * results are summed; the top's own glue is synthesized with the units as
  * black boxes.
  */
object EmitVerilog {
  /** xc7z045 capacity (Zynq-7000 data sheet DS190). */
  val Zc706: Synth.Area = Synth.Area(lut = 218600, ff = 437200, srl = 0, dsp = 900, carry = 0, ramb36 = 545, ramb18 = 0, lutram = 0)

  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val out = Paths.get(kv.getOrElse("--out", "build/verilog"))
    val fmt = FloatFormat.parse(kv.getOrElse("--float", "e8m23"))
    val test = if (kv.getOrElse("--triangle", "watertight").startsWith("m")) TriangleTest.Moller else TriangleTest.Watertight
    val box = if (kv.getOrElse("--rounding", "rne").startsWith("c")) BoxRounding.Conservative else BoxRounding.Nearest
    val synth = kv.getOrElse("--synth", "1") == "1"
    val generic = AccelConfig.zc706.copy(float = fmt)
    // With a scene package, the hardware is sized to that scene's needs.
    val cfg = kv.get("--package").filter(_.nonEmpty).fold(generic) { dir =>
      val pkg = ScenePackage.load(Paths.get(dir))
      val sized = pkg.sized(generic)
      println(s"verilog: sized to $dir: stack ${sized.stackDepth} (generic ${generic.stackDepth}), node index ${sized.nodeIndexBits} bits " +
        s"(${generic.nodeIndexBits}), triangle index ${sized.triIndexBits} bits (${generic.triIndexBits}), leaf ${sized.maxLeafSize} (${generic.maxLeafSize})")
      sized
    }
    val dp = FloatDatapath(fmt, test, box)
    run(cfg, dp, out, synth, kv.getOrElse("--jobs", "2").toInt)
  }

  def run(cfg: AccelConfig, dp: FloatDatapath, out: Path, synth: Boolean, jobs: Int): Unit = {
    Files.createDirectories(out)
    val t0 = System.nanoTime()
    val sv = Synth.emit(new RtAccel(cfg, dp))
    val mods = Synth.modules(sv)
    val top = mods.last
    val svFile = out.resolve(s"$top.sv")
    Files.writeString(svFile, sv)
    println(s"verilog: wrote $svFile (${mods.size} modules, ${sv.linesIterator.size} lines)")

    val waivers = out.resolve("verilator-waivers.vlt")
    Files.write(waivers, getClass.getResourceAsStream("/rtaccel/verilator-waivers.vlt").readAllBytes())
    val lintLog = out.resolve("lint.log")
    val lint = Seq("verilator", "--lint-only", "-Wall", waivers.toString, svFile.toString, "--top-module", top)
    val rc = (lint #> lintLog.toFile).!(ProcessLogger(line => Files.writeString(lintLog, line + "\n", java.nio.file.StandardOpenOption.CREATE, java.nio.file.StandardOpenOption.APPEND)))
    require(rc == 0, s"lint: `${lint.mkString(" ")}` found problems; see $lintLog")
    println(s"verilog: lint clean (verilator --lint-only -Wall, waivers in $waivers)")

    if (synth) {
      val units = mods.filter(m => Seq("FetchBVH_", "Traversal_", "LeafIntersect_", "RayBuffer_", "TaggedPortArbiter_").exists(m.startsWith))
      val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
      implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
      val jobsF = (units.map(u => u -> Future(Synth.yosys(svFile, u))) :+
        ("(top-level glue)" -> Future(Synth.yosys(svFile, top, blackboxes = units))))
      val rows = jobsF.map { case (u, f) => val a = Await.result(f, Duration.Inf); println(s"verilog: $u: $a"); u -> a }
      pool.shutdown()
      val md = ResourceTable(s"RtAccel ${dp.name}, ${cfg.numRayIds} ray IDs, stack ${cfg.stackDepth}", rows, Zc706,
        (System.nanoTime() - t0) / 1e9)
      Files.writeString(out.resolve("resources.md"), md)
      println(md)
    }
  }
}

/** The resource table, per unit, in total and against a device's capacity. */
object ResourceTable {
  def apply(title: String, rows: Seq[(String, Synth.Area)], device: Synth.Area, seconds: Double): String = {
    val total = rows.map(_._2).foldLeft(Synth.zero)(_ + _)
    def line(n: String, a: Synth.Area) = f"| $n | ${a.lut}%,d | ${a.ff}%,d | ${a.dsp}%,d | ${a.bram36}%.1f | ${a.lutram}%,d | ${a.carry}%,d |"
    def pct(x: Double, of: Double) = f"${100 * x / of}%.1f%%"
    val fits = Seq(device.lut.toDouble / total.lut.max(1), device.ff.toDouble / total.ff.max(1),
      device.dsp.toDouble / total.dsp.max(1), device.bram36 / total.bram36.max(0.5)).min.floor.toInt
    // Built line by line: stripMargin would eat the leading `|` of interpolated rows.
    (Seq(s"# Resources: $title", "",
      f"Generated by `make verilog` (Yosys 0.23 `synth_xilinx -family xc7`, per unit, summed) in $seconds%.0f s; do not edit.", "",
      "| unit | LUT | FF | DSP48 | BRAM36 | LUTRAM cells | CARRY4 |",
      "| --- | ---: | ---: | ---: | ---: | ---: | ---: |") ++
      rows.map { case (n, a) => line(n, a) } ++
      Seq(line("**total**", total), line("ZC706 (xc7z045) capacity", device),
        s"| share of the device | ${pct(total.lut, device.lut)} | ${pct(total.ff, device.ff)} | ${pct(total.dsp, device.dsp)} | ${pct(total.bram36, device.bram36)} | | |",
        "", s"Instances that fit on the device (by its scarcest resource): **$fits**.", "")).mkString("\n")
  }
}
