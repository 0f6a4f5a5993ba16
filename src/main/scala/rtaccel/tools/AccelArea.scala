package rtaccel.tools

import java.nio.file.{Files, Path}
import java.security.MessageDigest
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}

/** Area of a whole accelerator from its emitted SystemVerilog, summed from
  * per-unit Yosys runs (`synth_xilinx -family xc7`): each datapath unit
  * (RayPrep, BoxLane, PrimIntersect) with its sub-modules alone, then the
  * control (everything else) with those three as black boxes, each unit
  * counted once per instance (BboxIntersect holds K box lanes). A flattened run
  * of the whole FP-heavy design takes far longer than the units in parallel.
  *
  * The control run is flattened: it holds the core's memories (the ray stacks,
  * the ray buffer, the ray data), and only flattened does Yosys map them to
  * block RAM as Vivado would ([[FmaxEstimate.script]]); kept hierarchical, the
  * ray stacks alone became 2,304 RAM64M, 9,216 LUTs of distributed RAM. The
  * datapath units hold no memory and keep the hierarchy.
  *
  * Results are cached in `cacheDir`, keyed by a hash of the exact Verilog a
  * run reads with the datapath's name masked out: the same unit in two
  * configurations (say the box of the Moller and of the watertight variant,
  * when its Verilog is identical) is synthesised once, and `make verilog` and
  * `make speed-vs-error` share their results.
  */
object AccelArea {

  /** The datapath units, by module-name prefix (FloatDatapath's desiredName). */
  val datapathUnits: Seq[String] = Seq("RayPrep", "BoxLane", "PrimIntersect")

  /** The grid core's box unit (BoxTest.Grid: its FP32 node stage and K integer lanes), which stands
    * where the box lanes would and, like them, is measured whole.
    */
  val gridBoxUnit = "GridBboxIntersect"

  /** Every unit measured whole, by module-name prefix: the datapath units and the grid box unit. */
  val wholeUnits: Seq[String] = datapathUnits :+ gridBoxUnit
  val controlLabel = "control"

  final case class Module(name: String, text: String)

  def modules(sv: String): Seq[Module] =
    """(?ms)^module (\w+)\b.*?^endmodule\b[^\n]*\n?""".r.findAllMatchIn(sv).map(m =>
      Module(m.group(1), m.matched)
    ).toSeq

  /** `top` and every module it instantiates, transitively, in file order. */
  def subtree(mods: Seq[Module], top: String): Seq[Module] = {
    val byName = mods.map(m => m.name -> m).toMap
    val inst = """(?m)^\s+(\w+)\s+\w+\s*\(""".r
    val seen = collection.mutable.LinkedHashSet.empty[String]
    def visit(n: String): Unit = if (seen.add(n))
      inst.findAllMatchIn(byName(n).text).map(_.group(1)).filter(byName.contains).foreach(visit)
    require(byName.contains(top), s"module $top is not in the Verilog")
    visit(top)
    mods.filter(m => seen.contains(m.name))
  }

  private def hash(parts: String*): String = {
    val md = MessageDigest.getInstance("SHA-256")
    parts.foreach(p => md.update(p.getBytes("UTF-8")))
    md.digest().take(8).map(b => f"$b%02x").mkString
  }

  def toJson(a: Synth.Area): String = ujson.write(ujson.Obj(
    "lut" -> a.lut,
    "ff" -> a.ff,
    "srl" -> a.srl,
    "dsp" -> a.dsp,
    "carry" -> a.carry,
    "ramb36" -> a.ramb36,
    "ramb18" -> a.ramb18,
    "lutram" -> a.lutram
  ))
  def fromJson(j: ujson.Value): Synth.Area = Synth.Area(
    j("lut").num.toInt,
    j("ff").num.toInt,
    j("srl").num.toInt,
    j("dsp").num.toInt,
    j("carry").num.toInt,
    j("ramb36").num.toInt,
    j("ramb18").num.toInt,
    j("lutram").num.toInt
  )

  /** What a cached area means: a result stored under another version is not read (the run is redone). Version 2
    * counts distributed RAM in LUT sites ([[Synth.lutramSites]]), not in cells.
    */
  val cacheVersion = "area-v2"

  /** One cached Yosys run on `text` (the Verilog read), top `top`, black boxes `bb`. */
  private def cached(
      cacheDir: Path,
      label: String,
      mask: String,
      text: String,
      top: String,
      bb: Seq[String],
      flatten: Boolean = false
  ): Synth.Area = {
    val key = hash(
      cacheVersion,
      if (flatten) "flatten" else "hierarchy",
      text.replace(mask, "#"),
      top.replace(mask, "#"),
      bb.map(_.replace(mask, "#")).mkString(",")
    )
    val done = cacheDir.resolve(s"$label-$key.json")
    if (Files.exists(done)) fromJson(ujson.read(Files.readString(done)))
    else {
      // Per-process file names: two jobs of `make -j` may synthesise the same unit at once.
      val run = s"$label-$key.${ProcessHandle.current().pid()}"
      val sv = cacheDir.resolve(s"$run.sv")
      Files.writeString(sv, text)
      val a = Synth.yosys(sv, top, bb, Some(cacheDir.resolve(s"$run.yosys.log")), flatten)
      // Written whole then renamed, so a concurrent reader never sees half a file.
      val tmp = Files.createTempFile(cacheDir, label, ".tmp")
      Files.writeString(tmp, toJson(a))
      Files.move(
        tmp,
        done,
        java.nio.file.StandardCopyOption.REPLACE_EXISTING,
        java.nio.file.StandardCopyOption.ATOMIC_MOVE
      )
      a
    }
  }

  /** (unit, area) rows for the accelerator `top` in `sv` whose datapath is named `dpName`;
    * a unit's row is the area of all its instances. */
  def measure(sv: String, top: String, dpName: String, cacheDir: Path, jobs: Int): Seq[(String, Synth.Area)] = {
    Files.createDirectories(cacheDir)
    val mods = modules(sv)
    // Grid box tests (BoxTest.Grid) have no box lanes: the grid unit (its FP32 stage and K integer lanes)
    // takes their row.
    val unitTops = datapathUnits.map(u => u -> s"${u}_$dpName").map {
      case ("BoxLane", m) if !mods.exists(_.name == m) =>
        mods.find(_.name.startsWith(gridBoxUnit + "_")).fold("BoxLane" -> m)(g => gridBoxUnit -> g.name)
      case um => um
    }
    unitTops.foreach { case (_, m) => require(mods.exists(_.name == m), s"no module $m in the accelerator's Verilog") }
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    try {
      val units = unitTops.map { case (u, m) =>
        u -> Future(cached(cacheDir, u, dpName, subtree(mods, m).map(_.text).mkString, m, Nil))
      }
      val control =
        controlLabel -> Future(cached(cacheDir, controlLabel, dpName, sv, top, unitTops.map(_._2), flatten = true))
      // Units are instantiated only by modules that are themselves instantiated
      // once (RayPrep in FetchBVH, the K lanes in BboxIntersect, PrimIntersect
      // in LeafIntersect), so instance lines count the copies.
      val copies = unitTops.map { case (u, m) =>
        u -> (s"(?m)^\\s+$m\\s+\\w+\\s*\\(".r.findAllMatchIn(sv).size max 1)
      }.toMap
      (units :+ control).map { case (u, f) =>
        val a = Await.result(f, Duration.Inf)
        val n = copies.getOrElse(u, 1)
        u -> Seq.fill(n)(a).reduce(_ + _)
      }
    } finally pool.shutdown()
  }

  /** One box lane of `dp` alone (BboxIntersect holds `cfg.boxLanes` of them), cached like every unit. */
  def boxLane(dp: rtaccel.Datapath[_ <: chisel3.Data], cfg: rtaccel.AccelConfig, cacheDir: Path): Synth.Area = {
    Files.createDirectories(cacheDir)
    val sv = Synth.emit(dp.box(cfg))
    val top = modules(sv).last.name
    cached(cacheDir, "BoxLane", dp.name, sv, top, Nil)
  }

  /** The grid box unit of `cfg` (BoxTest.Grid: FP32 node stage and `cfg.boxLanes` grid lanes) alone, cached. */
  def gridUnit(dp: rtaccel.datapath.FloatDatapath, cfg: rtaccel.AccelConfig, cacheDir: Path): Synth.Area = {
    Files.createDirectories(cacheDir)
    val sv = Synth.emit(dp.gridBox(cfg))
    cached(cacheDir, gridBoxUnit, dp.name, sv, modules(sv).last.name, Nil)
  }

  def total(rows: Seq[(String, Synth.Area)]): Synth.Area = rows.map(_._2).foldLeft(Synth.zero)(_ + _)

  /** Whole instances of an accelerator of area `a` that fit on `device`, by its scarcest resource: every LUT
    * (logic and memory) against the device's LUTs, and the LUTs used as memory against its SLICEM LUTs
    * (`device.lutram`).
    */
  def instances(a: Synth.Area, device: Synth.Area): Int =
    Seq(
      device.lut.toDouble / a.lutSites.max(1),
      device.lutram.toDouble / a.lutMemory.max(1),
      device.ff.toDouble / a.ff.max(1),
      device.dsp.toDouble / a.dsp.max(1),
      device.bram36 / a.bram36.max(0.5)
    ).min.floor.toInt
}
