package rtaccel.tools

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.scene.ScenePackage
import rtaccel.system.{RtAccelSystem, SystemConfig}
import rtaccel.{AccelConfig, BoxTest, RtAccel}
import rtaccel.bvh.BvhLayout

import java.nio.file.{Files, Path, Paths}
import scala.sys.process._

/** `make verilog`: the accelerator's SystemVerilog for the ZC706 (xc7z045),
  * lint under `verilator --lint-only -Wall` (waivers with reasons in
  * verilator-waivers.vlt), and a Yosys resource table per unit and in total
  * beside the device's capacity (AccelArea: each datapath unit alone, the
  * control with them as black boxes, summed). With `--package`, the hardware
  * is sized to the scene and `sized.md` says what that saves against the
  * generic configuration. With `--system 1` (the default) it also emits the
  * ZC706 system top `rtaccel_system.sv` (RtAccelSystem: m_axi/s_axi ports)
  * with `--cores N` cores, by default as many as fit beside the system's own
  * units (SystemArea: fabric, node store, registers, DMAs, loader, each
  * synthesised alone; 2 without synthesis), lints it, and appends their
  * area and Fmax rows to the resource table.
  */
object EmitVerilog {

  /** xc7z045 capacity (Zynq-7000 data sheet DS190). `lutram` is the LUTs that can
    * hold memory (the SLICEM LUTs: 70,400 of the 218,600, the "LUT as Memory"
    * capacity Vivado's utilization report gives for this device).
    */
  val Zc706: Synth.Area =
    Synth.Area(lut = 218600, ff = 437200, srl = 0, dsp = 900, carry = 0, ramb36 = 545, ramb18 = 0, lutram = 70400)

  /** Yosys results shared with `make speed-vs-error` (keyed by the Verilog synthesised). */
  val areaCache: Path = Paths.get("build/area-cache")

  /** resources.md's title up to the stack depth: the datapath, the node layout, the box unit and the ray IDs, which
    * `make bench` checks before it takes the cores that fit and the Fmax estimate (VerilogFigures). The default
    * reads "RtAccel e8m23_wt_cons, 4-wide BVH nodes (4 box lanes), 128 ray IDs".
    */
  def coreTitle(datapath: String, cfg: AccelConfig): String = {
    val nodes = cfg.layout match {
      case BvhLayout.Nori                   => "nori BVH nodes"
      case w: BvhLayout.Wide if w.quantized => s"${w.name} (quantized ${w.k}-wide) BVH nodes"
      case w: BvhLayout.Wide                => s"${w.k}-wide BVH nodes"
    }
    val lanes = if (cfg.gridBox) s"${cfg.boxLanes} grid box lanes" else s"${cfg.boxLanes} box lanes"
    s"RtAccel $datapath, $nodes ($lanes), ${cfg.numRayIds} ray IDs"
  }

  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val out = Paths.get(kv.getOrElse("--out", "build/verilog"))
    val test = TriangleTest.parse(kv.getOrElse("--triangle", "watertight"))
    // Conservative boxes by default: no box a ray touches is ever culled (docs/kernels.md).
    val box = BoxRounding.parse(kv.getOrElse("--rounding", "conservative"))
    val layout = BvhLayout.parse(kv.getOrElse("--bvh", "4"))
    // FLOAT=auto: the smallest configuration the precision sweep found safe for
    // this variant, box and triangle formats; BOX_FLOAT= / TRI_FLOAT= override one unit.
    val (autoBox, autoTri) = kv.getOrElse("--float", "e8m23") match {
      case "auto" =>
        val (b, t, measuredOn) = SweepChoice.smallestSafePoint(SweepChoice.defaultJson, test, box)
        println(s"verilog: FLOAT=auto: boxes ${b.name}, triangles ${t.name}, the smallest safe configuration for " +
          s"${SweepChoice.variant(test, box)} in ${SweepChoice.defaultJson} (measured on $measuredOn nodes)")
        if (measuredOn != layout.name)
          println(
            s"verilog: note: BVH=${layout.name}, but the sweep found it safe on $measuredOn nodes (BVH=$measuredOn)"
          )
        (b, t)
      case other => val f = FloatFormat.parse(other); (f, f)
    }
    def fmtArg(k: String, default: FloatFormat) = kv.get(k).filter(_.nonEmpty).fold(default)(FloatFormat.parse)
    val (boxFmt, triFmt) = (fmtArg("--box-float", autoBox), fmtArg("--tri-float", autoTri))
    val synth = kv.getOrElse("--synth", "1") == "1"
    val jobs = kv.getOrElse("--jobs", "2").toInt
    // IDS=: rays in flight per core (the RayBuffer, traversal stacks and free list scale with it).
    val ids = kv.get("--ids").filter(_.nonEmpty).fold(AccelConfig.zc706.numRayIds)(_.toInt)
    // BOX_TEST=grid: a quantized layout's child boxes in the node's grid (AccelConfig refuses it elsewhere).
    val boxTest = BoxTest.parse(kv.getOrElse("--box-test", "fp32"))
    val generic = AccelConfig.zc706
      .copy(boxFloat = boxFmt, triFloat = triFmt, layout = layout, numRayIds = ids, boxTest = boxTest)
    // With a scene package, the hardware is sized to that scene's needs.
    val pkg = kv.get("--package").filter(_.nonEmpty).map(dir => ScenePackage.load(Paths.get(dir)))
    val cfg = pkg.fold(generic) { p =>
      val sized = p.sized(generic)
      println(
        s"verilog: sized to ${p.dir}: ${sized.layout.name} nodes (the image's), stack ${sized.stackDepth} (generic ${generic.stackDepth}), node index ${sized.nodeIndexBits} bits " +
          s"(${generic.nodeIndexBits}), triangle index ${sized.triIndexBits} bits (${generic.triIndexBits}), leaf ${sized.maxLeafSize} " +
          s"(${generic.maxLeafSize}), ${sized.floatName} (${generic.floatName}: exponents ${p.range.neededEmin}..${p.range.neededEmax} needed)"
      )
      if (sized.triFloat.manBits < p.range.neededManBits)
        println(s"verilog: warning: triangle format ${sized.triFloat.name} has ${sized.triFloat.manBits} mantissa bits; edges of ${p.range.smallestEdge} at coordinates " +
          s"up to ${p.range.maxAbs} need ${p.range.neededManBits} to keep every triangle intact after rounding")
      val why = p.misfits(sized)
      require(
        why.isEmpty,
        s"${p.dir}: no ${generic.floatName}-based configuration holds this scene:\n  " + why.mkString("\n  ")
      )
      sized
    }
    val dp = FloatDatapath.of(cfg, test, box)
    val measured = run(cfg, dp, out, synth, jobs)
    val rows = measured.map(_._1)
    if (kv.getOrElse("--system", "1") == "1") {
      val fits = rows.map(r => AccelArea.instances(AccelArea.total(r), Zc706).max(1))
      val coresArg = kv.get("--cores").map(_.toInt)
      val first = coresArg.orElse(fits).getOrElse(SystemConfig().cores)
      val svFile = system(SystemConfig(core = cfg, cores = first), dp, out)
      for ((coreRows, coreFmax) <- measured) {
        // The system's own units, then the cores that fit beside them: if fewer
        // than the core alone suggested, the system is emitted again with that many.
        val core = AccelArea.total(coreRows)
        def own(sv: Path) = SystemArea.measure(Files.readString(sv), areaCache, jobs, DelayModel.zynq7)
        def fits(n: Int, rows: Seq[FmaxEstimate.Row]) =
          SystemArea.coresThatFit(core, rows.map(_.area).foldLeft(Synth.zero)(_ + _), Zc706) >= n
        // Fewer cores than the core alone suggests may fit once the system's units are beside them, and those
        // units grow with the cores (their clients, arbiters and queues): each count is checked with the
        // system built at that count, from `first` down, and the system is emitted again at the one that fits.
        @scala.annotation.tailrec
        def settle(n: Int, rows: Seq[FmaxEstimate.Row]): (Int, Seq[FmaxEstimate.Row]) =
          if (coresArg.isDefined || n == 1 || fits(n, rows)) (n, rows)
          else {
            println(s"verilog: $n cores do not fit beside the system's units; trying ${n - 1}")
            settle(n - 1, own(system(SystemConfig(core = cfg, cores = n - 1), dp, out)))
          }
        val (cores, sysRows) = settle(first, own(svFile))
        val worst = (coreFmax ++ sysRows).maxBy(_.ns)
        Files.writeString(
          out.resolve("resources.md"),
          Files.readString(out.resolve("resources.md")) + "\n" +
            SystemArea.markdown(sysRows, cores, core, Zc706, SystemConfig().nodeStoreBytes) +
            s"System top: `rtaccel_system.sv` (RtAccelSystem) with $cores ${if (cores == 1) "core" else "cores"}" +
            s"${if (coresArg.isDefined) " (--cores)" else " (the cores that fit beside the system's units)"}, lint clean.\n\n" +
            f"**Estimated Fmax of the system** (its slowest unit, core or system, **${worst.unit}**): **${worst.mhz}%.0f MHz** (${worst.ns}%.2f ns). An ESTIMATE (docs/fmax.md).\n"
        )
      }
    }
    // Sized hardware: report what it saves against the generic configuration of the same arithmetic.
    for (p <- pkg; sizedRows <- rows) {
      val gdp = FloatDatapath.of(generic, test, box)
      println(s"verilog: the generic ${gdp.name} configuration, for comparison")
      val gRows = area(Synth.emit(new RtAccel(generic, gdp)), gdp, jobs)
      val md = SizedSavings(p.dir.toString, cfg, generic, AccelArea.total(sizedRows), AccelArea.total(gRows), Zc706)
      Files.writeString(out.resolve("sized.md"), md)
      println(md)
    }
  }

  private def area(sv: String, dp: FloatDatapath, jobs: Int): Seq[(String, Synth.Area)] =
    AccelArea.measure(sv, Synth.modules(sv).last, dp.name, areaCache, jobs)

  /** `verilator --lint-only -Wall` with the waivers (each with its reason in verilator-waivers.vlt); fails on any finding. */
  def lint(out: Path, svFile: Path, top: String, log: String): Unit = {
    val waivers = out.resolve("verilator-waivers.vlt")
    Files.write(waivers, getClass.getResourceAsStream("/rtaccel/verilator-waivers.vlt").readAllBytes())
    val lintLog = out.resolve(log)
    Files.deleteIfExists(lintLog)
    val cmd = Seq("verilator", "--lint-only", "-Wall", waivers.toString, svFile.toString, "--top-module", top)
    val rc = cmd.!(ProcessLogger(line =>
      Files.writeString(
        lintLog,
        line + "\n",
        java.nio.file.StandardOpenOption.CREATE,
        java.nio.file.StandardOpenOption.APPEND
      )
    ))
    require(rc == 0, s"lint: `${cmd.mkString(" ")}` found problems; see $lintLog")
    println(s"verilog: $top lint clean (verilator --lint-only -Wall, waivers in $waivers)")
  }

  /** The system top: emits build/verilog/rtaccel_system.sv and lints it. */
  def system(sys: SystemConfig, dp: FloatDatapath, out: Path): Path = {
    Files.createDirectories(out)
    val sv = Synth.emit(new RtAccelSystem(sys, dp))
    val svFile = out.resolve("rtaccel_system.sv")
    Files.writeString(svFile, sv)
    println(
      s"verilog: wrote $svFile (${sys.cores} cores of ${dp.name}, ${Synth.modules(sv).size} modules, ${sv.linesIterator.size} lines)"
    )
    lint(out, svFile, "rtaccel_system", "lint-system.log")
    svFile
  }

  /** Emits, lints and (with `synth`) measures; returns the per-unit rows. */
  def run(
      cfg: AccelConfig,
      dp: FloatDatapath,
      out: Path,
      synth: Boolean,
      jobs: Int
  ): Option[(Seq[(String, Synth.Area)], Seq[FmaxEstimate.Row])] = {
    Files.createDirectories(out)
    val t0 = System.nanoTime()
    val sv = Synth.emit(new RtAccel(cfg, dp))
    val mods = Synth.modules(sv)
    val top = mods.last
    val svFile = out.resolve(s"$top.sv")
    Files.writeString(svFile, sv)
    println(s"verilog: wrote $svFile (${mods.size} modules, ${sv.linesIterator.size} lines)")

    lint(out, svFile, top, "lint.log")

    Option.when(synth) {
      val rows = area(sv, dp, jobs)
      rows.foreach { case (u, a) => println(s"verilog: $u: $a") }
      val md = ResourceTable(
        s"${coreTitle(dp.name, cfg)}, stack ${cfg.stackDepth}",
        rows.map {
          case ("BoxLane", a) => s"BoxLane x${cfg.boxLanes} (BboxIntersect)" -> a
          case (AccelArea.gridBoxUnit, a) =>
            s"${AccelArea.gridBoxUnit} (FP32 node stage, ${cfg.boxLanes} grid lanes)" -> a
          case r => r
        },
        Zc706,
        (System.nanoTime() - t0) / 1e9
      )
      val t1 = System.nanoTime()
      val fmaxRows = FmaxEstimate.measure(sv, top, areaCache, jobs, DelayModel.zynq7)
      val fmax = FmaxEstimate.markdown(fmaxRows, DelayModel.zynq7, (System.nanoTime() - t1) / 1e9)
      Files.writeString(out.resolve("resources.md"), md + "\n" + fmax)
      println(md + "\n" + fmax)
      (rows, fmaxRows)
    }
  }
}

/** What hardware sized to a scene saves against the generic configuration. */
object SizedSavings {
  def apply(
      scene: String,
      sized: AccelConfig,
      generic: AccelConfig,
      s: Synth.Area,
      g: Synth.Area,
      device: Synth.Area
  ): String = {
    def pct(a: Double, b: Double) = if (b == 0) "-" else f"${100 * (b - a) / b}%.1f%%"
    def row(n: String, a: Double, b: Double) = f"| $n | $b%,.1f | $a%,.1f | ${pct(a, b)} |"
    (Seq(
      s"# Hardware sized to $scene",
      "",
      "| parameter | generic ZC706 | sized |",
      "| --- | --- | --- |",
      s"| BVH layout | ${generic.layout.name} | ${sized.layout.name} |",
      s"| stack depth | ${generic.stackDepth} | ${sized.stackDepth} |",
      s"| node index bits | ${generic.nodeIndexBits} | ${sized.nodeIndexBits} |",
      s"| triangle index bits | ${generic.triIndexBits} | ${sized.triIndexBits} |",
      s"| largest leaf | ${generic.maxLeafSize} | ${sized.maxLeafSize} |",
      s"| number format (box+triangle) | ${generic.floatName} | ${sized.floatName} |",
      "",
      "| resource | generic | sized | saved |",
      "| --- | ---: | ---: | ---: |",
      row("LUT", s.lutSites, g.lutSites),
      row("FF", s.ff, g.ff),
      row("DSP48", s.dsp, g.dsp),
      row("BRAM36", s.bram36, g.bram36),
      "",
      s"Instances on the ZC706: generic ${AccelArea.instances(g, device)}, sized ${AccelArea.instances(s, device)}.",
      ""
    )).mkString("\n")
  }
}

/** The resource table, per unit, in total and against a device's capacity. */
object ResourceTable {
  def apply(title: String, rows: Seq[(String, Synth.Area)], device: Synth.Area, seconds: Double): String = {
    val total = rows.map(_._2).foldLeft(Synth.zero)(_ + _)
    def cells(n: String, lut: Int, lutMemory: Int, a: Synth.Area) =
      f"| $n | $lut%,d | $lutMemory%,d | ${a.ff}%,d | ${a.dsp}%,d | ${a.bram36}%.1f | ${a.carry}%,d |"
    def line(n: String, a: Synth.Area) = cells(n, a.lutSites, a.lutMemory, a)
    def pct(x: Double, of: Double) = f"${100 * x / of}%.1f%%"
    val fits = AccelArea.instances(total, device)
    // Built line by line: stripMargin would eat the leading `|` of interpolated rows.
    (Seq(
      s"# Resources: $title",
      "",
      f"Generated by `make verilog` (Yosys 0.23 `synth_xilinx -family xc7`; each datapath unit alone, the control with them as black boxes and flattened, so that its memories map to block RAM as Vivado infers them; summed) in $seconds%.0f s; do not edit. " +
        "LUT counts every LUT used, as logic or as memory; LUT as memory (distributed RAM and shift registers) also has to fit in the device's SLICEM LUTs.",
      "",
      "| unit | LUT | LUT as memory | FF | DSP48 | BRAM36 | CARRY4 |",
      "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"
    ) ++
      rows.map { case (n, a) => line(n, a) } ++
      Seq(
        line("**total**", total),
        // The device's LUTs, of which `lutram` (its SLICEM LUTs) can hold memory.
        cells("ZC706 (xc7z045) capacity", device.lut, device.lutram, device),
        s"| share of the device | ${pct(total.lutSites, device.lut)} | ${pct(total.lutMemory, device.lutram)} | ${pct(
            total.ff,
            device.ff
          )} | ${pct(total.dsp, device.dsp)} | ${pct(total.bram36, device.bram36)} | |",
        "",
        s"Instances that fit on the device (by its scarcest resource): **$fits**.",
        ""
      )).mkString("\n")
  }
}
