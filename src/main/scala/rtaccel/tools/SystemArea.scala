package rtaccel.tools

import java.nio.file.Path
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}

/** Area and Fmax estimate of the ZC706 system's own units: what
  * SystemCore holds besides its cores, each synthesised alone from the
  * emitted `rtaccel_system.sv` in one cached Yosys run ([[FmaxEstimate.run]]:
  * the same script gives the cell counts and the longest path), never the
  * whole design flattened. MemoryFabric is measured with the NodeStore and
  * TriStore black-boxed (each store has its own row: its BRAM), SystemCore with
  * every unit and core black-boxed (its own glue: the batch registers, the
  * ray distribution and the counters). Flattened before memory mapping
  * ([[FmaxEstimate.script]]), so the node store's memory is block RAM.
  */
object SystemArea {

  /** The units, by module-name prefix, in the table's order. */
  val units: Seq[String] =
    Seq("MemoryFabric", "NodeStore", "TriStore", "AxiLiteRegs", "RayDma", "HitDma", "SceneLoader", "SystemCore")

  /** The core, black-boxed in SystemCore's row (its area is the core table's). */
  val corePrefix = "RtAccel"

  private def named(names: Seq[String], prefix: String): Option[String] =
    names.find(n => n == prefix || n.startsWith(prefix + "_"))

  /** `top` and what it instantiates, transitively, not descending into `stops` (kept, as black boxes). */
  def subtreeStopping(mods: Seq[AccelArea.Module], top: String, stops: Set[String]): Seq[AccelArea.Module] = {
    val byName = mods.map(m => m.name -> m).toMap
    val inst = """(?m)^\s+(\w+)\s+\w+\s*\(""".r
    val seen = collection.mutable.LinkedHashSet.empty[String]
    def visit(n: String): Unit = if (seen.add(n) && !stops.contains(n))
      inst.findAllMatchIn(byName(n).text).map(_.group(1)).filter(byName.contains).foreach(visit)
    visit(top)
    mods.filter(m => seen.contains(m.name))
  }

  /** Each unit present in `mods` (a system without a node store has no NodeStore row): its name, module, the
    * source synthesised for it, and the modules black-boxed in it (their own text stays: `blackbox` keeps their
    * ports). */
  def plan(mods: Seq[AccelArea.Module]): Seq[(String, String, String, Seq[String])] = {
    val names = mods.map(_.name)
    val present = units.flatMap(u => named(names, u).map(u -> _))
    val core = named(names, corePrefix).toSeq
    present.map { case (u, m) =>
      val bb = u match {
        case "MemoryFabric" => present.collect { case (s, n) if s == "NodeStore" || s == "TriStore" => n }
        case "SystemCore"   => present.collect { case (o, n) if o != u => n } ++ core
        case _              => Nil
      }
      val inside = subtreeStopping(mods, m, bb.toSet)
      (u, m, inside.map(_.text).mkString, bb.filter(b => inside.exists(_.name == b)))
    }
  }

  /** One row per unit present in `sv` ([[plan]]). */
  def measure(sv: String, cacheDir: Path, jobs: Int, model: DelayModel): Seq[FmaxEstimate.Row] = {
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    try {
      val futures = plan(AccelArea.modules(sv)).map { case (u, m, text, bb) =>
        Future {
          val (a, p) = FmaxEstimate.run(cacheDir, u, text, m, bb, flatten = true, model = model)
          println(f"system: $u: $a, ${p.described}, ${p.ns}%.2f ns")
          FmaxEstimate.Row(u, m, a, p, p.ns)
        }
      }
      futures.map(Await.result(_, Duration.Inf))
    } finally pool.shutdown()
  }

  /** `runMain rtaccel.tools.SystemArea <rtaccel_system.sv> [jobs]`: the rows for an already emitted system. */
  def main(args: Array[String]): Unit = {
    require(args.nonEmpty, "usage: SystemArea <rtaccel_system.sv> [jobs]")
    val rows = measure(
      java.nio.file.Files.readString(Path.of(args(0))),
      EmitVerilog.areaCache,
      args.lift(1).fold(2)(_.toInt),
      DelayModel.zynq7
    )
    rows.foreach(r =>
      println(
        f"| ${r.unit} | ${r.area.lutSites}%,d | ${r.area.ff}%,d | ${r.area.dsp}%,d | ${r.area.bram36}%.1f | ${r.area.lutMemory}%,d | ${r.path.described} | ${r.ns}%.2f | ${r.mhz}%.0f |"
      )
    )
  }

  /** Whole cores of area `core` that fit on `device` beside `own` (the system's units), by the scarcest resource. */
  def coresThatFit(core: Synth.Area, own: Synth.Area, device: Synth.Area): Int = {
    val left = Synth.Area(
      device.lut - own.lutSites,
      device.ff - own.ff,
      0,
      device.dsp - own.dsp,
      0,
      device.ramb36 - own.ramb36 - (own.ramb18 + 1) / 2,
      0,
      device.lutram - own.lutMemory
    )
    AccelArea.instances(core, left).max(0)
  }

  /** The section appended to resources.md. */
  def markdown(
      rows: Seq[FmaxEstimate.Row],
      cores: Int,
      core: Synth.Area,
      device: Synth.Area,
      nodeStoreBytes: Int,
      triStoreBytes: Int = rtaccel.system.SystemConfig().triStoreBytes,
      storeCopies: Int = rtaccel.system.SystemConfig().storeCopies
  ): String = {
    val own = rows.map(_.area).foldLeft(Synth.zero)(_ + _)
    val coresArea = Seq.fill(cores)(core).foldLeft(Synth.zero)(_ + _)
    val total = own + coresArea
    def cells(a: Synth.Area) = f"${a.lutSites}%,d | ${a.ff}%,d | ${a.dsp}%,d | ${a.bram36}%.1f | ${a.lutMemory}%,d"
    def pct(x: Double, of: Double) = f"${100 * x / of}%.1f%%"
    // At most `cores`: more cores bring more of the system's units (their clients, arbiters and queues), which
    // this system, built with `cores`, does not hold.
    val fit = coresThatFit(core, own, device).min(cores)
    val worst = rows.maxBy(_.ns)
    (Seq(
      s"## The system's own units (rtaccel_system, $cores ${if (cores == 1) "core" else "cores"})",
      "",
      s"Each unit synthesised alone from `rtaccel_system.sv` (the Fmax estimate's Yosys run, flattened first so that memories map to block RAM; MemoryFabric with the NodeStore and TriStore black-boxed, " +
        s"SystemCore with its units and cores black-boxed). Node store: ${nodeStoreBytes / 1024} KiB, " +
        s"triangle store: ${triStoreBytes / 1024} KiB, each $storeCopies block-RAM ${if (storeCopies == 1) "copy"
          else "copies"} " +
        s"(dual-ported; ${if (cores > 2 * storeCopies) "the cores share its two ports" else "a port per core"}). ESTIMATE, as above.",
      "",
      "| unit | LUT | FF | DSP48 | BRAM36 | LUT as memory | path cells: from → to | ns | MHz |",
      "| --- | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: |"
    ) ++
      rows.map(r => f"| ${r.unit} | ${cells(r.area)} | ${r.path.described} | ${r.ns}%.2f | ${r.mhz}%.0f |") ++
      Seq(
        s"| **system units** | ${cells(own)} | | | |",
        s"| $cores x core (table above) | ${cells(coresArea)} | | | |",
        s"| **system total** | ${cells(total)} | | | |",
        s"| share of the device | ${pct(total.lutSites, device.lut)} | ${pct(total.ff, device.ff)} | ${pct(
            total.dsp,
            device.dsp
          )} | ${pct(total.bram36, device.bram36)} | ${pct(total.lutMemory, device.lutram)} | | | |",
        "",
        s"Cores that fit beside the system's own units (by the scarcest resource): **$fit**.",
        f"Slowest system unit: **${worst.unit}**, ${worst.mhz}%.0f MHz (${worst.ns}%.2f ns).",
        ""
      )).mkString("\n")
  }
}
