package rtaccel.tools

import java.nio.file.{Files, Path}
import java.security.MessageDigest
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._

/** Fmax estimate per unit (docs/fmax.md): each unit of an emitted design is
  * synthesised alone (Yosys 0.23 `synth_xilinx -family xc7`, flattened; the
  * datapath units black-boxed inside the control units) and written as a JSON
  * netlist, and [[TimingGraph]] finds its longest register-to-register path
  * by a [[DelayModel]]'s delay. No placement or routing: an ESTIMATE.
  *
  * Cut (treated as registers): DSP48E1, block RAM, SRLs, I/O buffers and black
  * boxes; distributed RAM is read through a LUT arc. A DSP48E1 without its
  * registers ([[TimingGraph]]) makes its unit's row say that its multiplies
  * are not timed. A unit's ports count as
  * register boundaries: within the datapath every unit input comes from a
  * register or another unit's registered output.
  */
object FmaxEstimate {

  /** A path's cell types in order (inverters included), its start and end, and its delay by the model it was found
    * with; `unregisteredDsp` lists the unit's DSP48E1s that cut paths without their registers
    * ([[TimingGraph]]), whose multiplies the estimate does not time. */
  final case class PathCells(
      cells: Seq[String],
      ns: Double = Double.NaN,
      from: String = "",
      to: String = "",
      unregisteredDsp: Seq[String] = Nil
  ) {
    private def n(p: String => Boolean) = cells.count(p)
    def luts: Int = n(c => DelayModel.kind(c) == "LUT")
    def muxf: Int = n(c => c == "MUXF7" || c == "MUXF8")
    def carry4: Int = n(_ == "CARRY4")
    def inv: Int = n(_ == "INV")
    def other: Int = cells.size - luts - muxf - carry4 - inv
    def summary: String =
      s"${cells.size} (${luts} LUT, ${muxf} MUXF, ${carry4} CARRY4${if (inv > 0) s", $inv INV" else ""}${if (other > 0) s", $other other"
        else ""})"

    /** The summary and, when known, where the path starts and ends (as a markdown table cell); a unit with
      * unregistered DSP48E1s says so, since its figure leaves their multiplies out. */
    def described: String = {
      val path =
        if (from.isEmpty && to.isEmpty) summary
        else s"$summary: `${from.replace("|", "\\|")}` → `${to.replace("|", "\\|")}`"
      if (unregisteredDsp.isEmpty) path
      else s"$path; **${unregisteredDsp.size} DSP48E1 without their registers, not timed**"
    }
  }
  final case class Row(unit: String, module: String, area: Synth.Area, path: PathCells, ns: Double) {
    def mhz: Double = 1000.0 / ns
  }

  /** With `flatten`, synth_xilinx flattens before it maps memories: firtool
    * emits each memory as a module with one clock input per port, and Yosys
    * 0.23 does not merge a read port's address register into a port whose
    * clock differs from the write port's, so hierarchically every such
    * memory is read asynchronously and lands in LUTRAM whatever its size.
    * Flattened, the ports share the one clock and block RAM is inferred
    * (Vivado infers it either way). Every Fmax row uses it (the system's
    * units, [[SystemArea]], and the core's, [[measure]]), and so does the
    * core's area ([[AccelArea]]: its control run): a memory is timed as the
    * kind Vivado builds, block RAM with its own clock-to-out or distributed
    * RAM read through its LUTs ([[TimingGraph]]).
    *
    * The netlist is written with `json` on the top alone rather than
    * `write_json`, which would add the 400-odd cell library modules
    * synth_xilinx loads (ten times the unit's own netlist). */
  def script(sv: Path, top: String, blackboxes: Seq[String], flatten: Boolean = false, json: Path): String = {
    val bb = if (blackboxes.isEmpty) "" else s"blackbox ${blackboxes.mkString(" ")}; "
    s"read_verilog -sv $sv; ${bb}synth_xilinx -family xc7${if (flatten) " -flatten"
      else ""} -top $top; flatten; stat; json -o $json $top"
  }

  /** Bumped when the path search or the cached fields change, so that older cache entries are not read. */
  val cacheVersion = "fmax-delay-v1"

  private def hash(parts: String*): String = {
    val md = MessageDigest.getInstance("SHA-256")
    parts.foreach(p => md.update(p.getBytes("UTF-8")))
    md.digest().take(8).map(b => f"$b%02x").mkString
  }

  private def pathJson(p: PathCells): ujson.Value = ujson.Obj(
    "cells" -> ujson.Arr.from(p.cells),
    "ns" -> p.ns,
    "from" -> p.from,
    "to" -> p.to,
    "unregisteredDsp" -> ujson.Arr.from(p.unregisteredDsp)
  )
  private def pathOf(j: ujson.Value): PathCells = PathCells(
    j("cells").arr.map(_.str).toSeq,
    j("ns").num,
    j("from").str,
    j("to").str,
    j.obj.get("unregisteredDsp").fold(Seq.empty[String])(_.arr.map(_.str).toSeq)
  )

  /** A cache entry without an `unregisteredDsp` field (from a pass that did not check DSP48s) is still right for a unit
    * without DSP48s (most control units, whose runs are the longest), and is run again otherwise. */
  private def current(j: ujson.Value): Boolean =
    j("path").obj.contains("unregisteredDsp") || AccelArea.fromJson(j("area")).dsp == 0

  /** The longest path by `model` of `top` in the Yosys JSON netlist at `json`. */
  def longestPath(json: Path, top: String, model: DelayModel): PathCells = {
    val p = TimingGraph.longest(ujson.read(ujson.Readable.fromPath(json)), top, model)
    PathCells(p.cells, p.ns, p.from, p.to, p.unregisteredDsp)
  }

  /** Writes `text` to `<dir>/<stem>.sv` and runs [[script]] on it: (the source, Yosys's log, the JSON netlist). */
  def synthesise(
      dir: Path,
      stem: String,
      text: String,
      top: String,
      bb: Seq[String],
      flatten: Boolean
  ): (Path, Path, Path) = {
    val sv = dir.resolve(s"$stem.sv")
    val log = dir.resolve(s"$stem.yosys.log")
    val netlist = dir.resolve(s"$stem.netlist.json")
    Files.writeString(sv, text)
    val rc =
      Seq("yosys", "-q", "-l", log.toString, "-p", script(sv, top, bb, flatten, netlist)).!(ProcessLogger(_ => ()))
    require(rc == 0, s"yosys failed on $top from $sv (exit $rc); see $log")
    (sv, log, netlist)
  }

  /** One cached Yosys run: area and longest path by `model`'s delay of `top` in `text`. The model is part of the
    * cache key: the path it picks depends on its figures. */
  def run(
      cacheDir: Path,
      label: String,
      text: String,
      top: String,
      bb: Seq[String],
      flatten: Boolean = false,
      model: DelayModel = DelayModel.zynq7
  ): (Synth.Area, PathCells) = {
    Files.createDirectories(cacheDir)
    val key = hash(
      AccelArea.cacheVersion,
      cacheVersion,
      model.toString,
      text,
      top,
      bb.mkString(","),
      script(Path.of("x"), top, bb, flatten, Path.of("y"))
    )
    val done = cacheDir.resolve(s"fmax-$label-$key.json")
    val cached = Option.when(Files.exists(done))(ujson.read(Files.readString(done))).filter(current)
    cached.fold {
      val (sv, log, netlist) =
        synthesise(cacheDir, s"fmax-$label-$key.${ProcessHandle.current().pid()}", text, top, bb, flatten)
      val area = Synth.parseTotal(Files.readString(log), log)
      val path = longestPath(netlist, top, model)
      val json = ujson.Obj("area" -> ujson.read(AccelArea.toJson(area)), "path" -> pathJson(path))
      val tmp = Files.createTempFile(cacheDir, label, ".tmp")
      Files.writeString(tmp, ujson.write(json))
      Files.move(
        tmp,
        done,
        java.nio.file.StandardCopyOption.REPLACE_EXISTING,
        java.nio.file.StandardCopyOption.ATOMIC_MOVE
      )
      Files.deleteIfExists(sv)
      Files.deleteIfExists(netlist)
      (area, path)
    }(j => (AccelArea.fromJson(j("area")), pathOf(j("path"))))
  }

  /** Memories, queues and arbiters firtool and chisel3.util emit: part of their parent's row. */
  private def isPlumbing(m: String): Boolean =
    m.matches(""".*_\d+x\d+(_\d+)?""") || m.startsWith("Queue") || m.startsWith("HeadQueue") ||
      m.startsWith("RamQueue") || m.startsWith("RRArbiter")

  /** The units of `top` in `sv`, in file order: each FP unit, each datapath
    * unit (whole), and every other non-plumbing module with the datapath
    * units black-boxed (the top's row is the whole control). */
  def units(sv: String, top: String): Seq[(String, String, Seq[String])] = {
    val mods = AccelArea.subtree(AccelArea.modules(sv), top)
    val names = mods.map(_.name)
    val dpTops = names.filter(n => AccelArea.wholeUnits.exists(u => n.startsWith(u + "_")))
    val inDatapath = dpTops.flatMap(t => AccelArea.subtree(mods, t).map(_.name)).toSet
    names.flatMap { n =>
      if (n.startsWith("Fp")) Some((n, n, Nil))
      else if (dpTops.contains(n)) Some((n, n, Nil))
      else if (inDatapath.contains(n) || isPlumbing(n)) None
      else {
        val inside = AccelArea.subtree(mods, n).map(_.name).toSet
        Some((if (n == top) s"$n (control)" else n, n, dpTops.filter(inside.contains)))
      }
    }
  }

  /** Module `m`'s source with everything inside its black boxes `bb` left out. */
  def unitText(mods: Seq[AccelArea.Module], m: String, bb: Seq[String]): String =
    AccelArea.subtree(mods, m).filterNot(x =>
      bb.exists(b => x.name != b && AccelArea.subtree(mods, b).exists(_.name == x.name))
    ).map(_.text).mkString

  def measure(sv: String, top: String, cacheDir: Path, jobs: Int, model: DelayModel): Seq[Row] = {
    val mods = AccelArea.modules(sv)
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    try {
      val us = units(sv, top)
      val futures = us.map { case (label, m, bb) =>
        val text = unitText(mods, m, bb)
        label -> Future {
          val (a, p) = run(cacheDir, m.takeWhile(_ != '_'), text, m, bb, flatten = true, model = model)
          println(f"fmax: $label: ${p.described}, ${p.ns}%.2f ns")
          p.unregisteredDsp.foreach(d => println(s"fmax: WARNING: $label: DSP48E1 not timed: $d"))
          Row(label, m, a, p, p.ns)
        }
      }
      futures.map { case (_, f) => Await.result(f, Duration.Inf) }
    } finally pool.shutdown()
  }

  /** `runMain rtaccel.tools.FmaxEstimate <design.sv> [jobs]`: the table for an already emitted design. */
  def main(args: Array[String]): Unit = {
    require(args.nonEmpty, "usage: FmaxEstimate <design.sv> [jobs]")
    val sv = Files.readString(Path.of(args(0)))
    val t0 = System.nanoTime()
    val rows =
      measure(sv, Synth.modules(sv).last, EmitVerilog.areaCache, args.lift(1).fold(2)(_.toInt), DelayModel.zynq7)
    println(markdown(rows, DelayModel.zynq7, (System.nanoTime() - t0) / 1e9))
  }

  /** The markdown section appended to resources.md. */
  def markdown(rows: Seq[Row], model: DelayModel, seconds: Double): String = {
    val worst = rows.maxBy(_.ns)
    def line(r: Row) =
      f"| ${r.unit} | ${r.area.lut}%,d | ${r.area.ff}%,d | ${r.area.dsp}%,d | ${r.area.bram36}%.1f | ${r.path.described} | ${r.ns}%.2f | ${r.mhz}%.0f |"
    (Seq(
      "## Fmax estimate per unit (ESTIMATE)",
      "",
      f"Each unit synthesised alone (`synth_xilinx -family xc7`, then flattened; datapath units black-boxed in control units), the longest register-to-register path by the delay model *${model.name}* over its mapped netlist (docs/fmax.md) in $seconds%.0f s. Area here is per instance (the table above counts instances); flattened before memory mapping, so memories are block RAM or distributed RAM as Vivado infers them, timed as such; the LUT column counts logic LUTs (the table above adds those that hold memory). No placement or routing: an estimate, not a timing sign-off.",
      "",
      "| unit | LUT (logic) | FF | DSP48 | BRAM36 | path cells: from → to | ns | MHz |",
      "| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: |"
    ) ++
      rows.map(line) ++
      Seq(
        "",
        f"Estimated system Fmax (slowest unit, **${worst.unit}**): **${worst.mhz}%.0f MHz** (${worst.ns}%.2f ns)."
      ) ++ {
        val untimed = rows.filter(_.path.unregisteredDsp.nonEmpty)
        if (untimed.isEmpty) Nil
        else
          Seq(
            "",
            s"**Not timed**: DSP48E1s without their registers in ${untimed.map(_.unit).mkString(", ")} (their multiplies are in the same cycle as fabric logic, which the estimate prices at 0 ns; docs/fmax.md)."
          )
      } :+ "").mkString("\n")
  }
}
