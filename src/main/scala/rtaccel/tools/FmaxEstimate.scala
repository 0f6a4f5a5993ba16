package rtaccel.tools

import java.nio.file.{Files, Path}
import java.security.MessageDigest
import scala.concurrent.duration.Duration
import scala.concurrent.{Await, ExecutionContext, Future}
import scala.sys.process._

/** Fmax estimate per unit (docs/fmax.md): each unit of an emitted design is
  * synthesised alone (Yosys 0.23 `synth_xilinx -family xc7`, flattened; the
  * datapath units black-boxed inside the control units), then `ltp` finds its
  * longest topological path with flip-flops cut out (`ltp -noff t:FD* %n`, as
  * plain `-noff` does not cut at FDRE) and the cells on it are counted and
  * turned into ns by a [[DelayModel]]. `ltp` ranks paths by cell count, so a
  * carry chain of many fast CARRY4 cells can hide a slower path of LUTs and
  * MUXFs with fewer cells: a second `ltp` cuts the CARRY4 cells too, and the
  * slower of the two paths is the unit's. Even so the slowest path may mix
  * both kinds and placement is unknown: an ESTIMATE.
  *
  * Also cut (treated as registers): DSP48E1, RAMB and LUTRAM/SRL cells (their
  * internal and read paths are not modelled), I/O buffers and black boxes. A
  * unit's ports count as register boundaries: within the datapath every unit
  * input comes from a register or another unit's registered output.
  */
object FmaxEstimate {
  final case class PathCells(cells: Seq[String]) {
    private def n(p: String => Boolean) = cells.count(p)
    def luts: Int = n(c => DelayModel.kind(c) == "LUT")
    def muxf: Int = n(c => c == "MUXF7" || c == "MUXF8")
    def carry4: Int = n(_ == "CARRY4")
    def inv: Int = n(_ == "INV")
    def other: Int = cells.size - luts - muxf - carry4 - inv
    def summary: String =
      s"${cells.size} (${luts} LUT, ${muxf} MUXF, ${carry4} CARRY4${if (inv > 0) s", $inv INV" else ""}${if (other > 0) s", $other other"
        else ""})"
  }
  final case class Row(unit: String, module: String, area: Synth.Area, path: PathCells, ns: Double) {
    def mhz: Double = 1000.0 / ns
  }

  /** Cell types renamed into the cell names before `ltp`, so that the path it prints names its types. */
  val namedTypes: Seq[String] = Seq("LUT1", "LUT2", "LUT3", "LUT4", "LUT5", "LUT6", "MUXF7", "MUXF8", "CARRY4", "INV")
  private val cutTypes = Seq("t:FD*", "t:DSP48E1", "t:RAM*", "t:SRL*", "t:IBUF", "t:OBUF", "t:BUFG")

  /** With `flatten`, synth_xilinx flattens before it maps memories: firtool
    * emits each memory as a module with one clock input per port, and Yosys
    * 0.23 does not merge a read port's address register into a port whose
    * clock differs from the write port's, so hierarchically every such
    * memory is read asynchronously and lands in LUTRAM whatever its size.
    * Flattened, the ports share the one clock and block RAM is inferred
    * (Vivado infers it either way). The system's units use it
    * ([[SystemArea]]), and so does the core's area ([[AccelArea]]: its
    * control run). The core's Fmax rows keep the hierarchical run: there a
    * memory is distributed RAM, whose cells cut paths as block RAM's do, and
    * their area column counts LUTs as logic only. */
  def script(sv: Path, top: String, blackboxes: Seq[String], flatten: Boolean = false): String = {
    val bb = if (blackboxes.isEmpty) "" else s"blackbox ${blackboxes.mkString(" ")}; "
    val rename = namedTypes.map(t => s"rename -enumerate -pattern c${t}_% t:$t; ").mkString
    val cut = (cutTypes ++ blackboxes.map(b => s"t:$b")).reduceLeft((a, b) => s"$a $b %u")
    s"read_verilog -sv $sv; ${bb}synth_xilinx -family xc7${if (flatten) " -flatten"
      else ""} -top $top; flatten; stat; ${rename}ltp -noff $cut %n; ltp -noff $cut t:CARRY4 %u %n"
  }

  private val pathHead = """Longest topological path in \S+ \(length=(\d+)\):""".r
  private val via = """\(via (\S+)\)""".r
  private val typed = """^c([A-Z0-9]+)_\d+$""".r

  /** The cells on the path `ltp` printed last in `log`, by type ("other" for unnamed cells). */
  def parsePath(log: String, file: String): PathCells = {
    val at = log.lastIndexOf("Longest topological path in")
    require(at >= 0, s"$file: no 'Longest topological path' in the Yosys log")
    parseBlock(log.substring(at), file)
  }

  /** Every path `ltp` printed in `log`, in order. */
  def parsePaths(log: String, file: String): Seq[PathCells] = {
    val marker = "Longest topological path in"
    val starts = Iterator.iterate(log.indexOf(marker))(i => log.indexOf(marker, i + 1)).takeWhile(_ >= 0).toSeq
    require(starts.nonEmpty, s"$file: no 'Longest topological path' in the Yosys log")
    starts.map(i => parseBlock(log.substring(i), file))
  }

  private def parseBlock(from: String, file: String): PathCells = {
    val block = from.linesIterator.drop(1).takeWhile(l => l.trim.matches("""\d+:.*""")).toSeq
    val length = pathHead.findFirstMatchIn(from).map(_.group(1).toInt).get
    val cells = block.flatMap(l => via.findFirstMatchIn(l).map(_.group(1))).map {
      case typed(t) if namedTypes.contains(t) => t
      case _                                  => "other"
    }
    require(cells.size == length, s"$file: ltp reported length $length but ${cells.size} cells were parsed")
    PathCells(cells)
  }

  /** The slower by `model` of the paths both `ltp` runs found. */
  def slowest(paths: Seq[PathCells], model: DelayModel): PathCells = paths.maxBy(p => model.pathNs(p.cells))

  private def hash(parts: String*): String = {
    val md = MessageDigest.getInstance("SHA-256")
    parts.foreach(p => md.update(p.getBytes("UTF-8")))
    md.digest().take(8).map(b => f"$b%02x").mkString
  }

  /** One cached Yosys run: area and slowest path (by `model`) of `top` in `text`. */
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
    val key = hash(AccelArea.cacheVersion, text, top, bb.mkString(","), script(Path.of("x"), top, bb, flatten))
    val done = cacheDir.resolve(s"fmax-$label-$key.json")
    if (Files.exists(done)) {
      val j = ujson.read(Files.readString(done))
      (AccelArea.fromJson(j("area")), slowest(j("paths").arr.map(p => PathCells(p.arr.map(_.str).toSeq)).toSeq, model))
    } else {
      val stem = s"fmax-$label-$key.${ProcessHandle.current().pid()}"
      val sv = cacheDir.resolve(s"$stem.sv")
      val log = cacheDir.resolve(s"$stem.yosys.log")
      Files.writeString(sv, text)
      val rc = Seq("yosys", "-q", "-l", log.toString, "-p", script(sv, top, bb, flatten)).!(ProcessLogger(_ => ()))
      require(rc == 0, s"yosys failed on $top from $sv (exit $rc); see $log")
      val logText = Files.readString(log)
      val area = Synth.parseTotal(logText.substring(0, logText.indexOf("Longest topological path in").max(0)), log)
      val paths = parsePaths(logText, log.toString)
      require(paths.size == 2, s"$log: ${paths.size} ltp paths, expected 2 (with and without carry chains)")
      val path = slowest(paths, model)
      val json =
        ujson.Obj("area" -> ujson.read(AccelArea.toJson(area)), "paths" -> paths.map(p => ujson.Arr.from(p.cells)))
      val tmp = Files.createTempFile(cacheDir, label, ".tmp")
      Files.writeString(tmp, ujson.write(json))
      Files.move(
        tmp,
        done,
        java.nio.file.StandardCopyOption.REPLACE_EXISTING,
        java.nio.file.StandardCopyOption.ATOMIC_MOVE
      )
      Files.deleteIfExists(sv)
      (area, path)
    }
  }

  /** Memories, queues and arbiters firtool and chisel3.util emit: part of their parent's row. */
  private def isPlumbing(m: String): Boolean =
    m.matches(""".*_\d+x\d+""") || m.startsWith("Queue") || m.startsWith("HeadQueue") || m.startsWith("RRArbiter")

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

  def measure(sv: String, top: String, cacheDir: Path, jobs: Int, model: DelayModel): Seq[Row] = {
    val mods = AccelArea.modules(sv)
    val pool = java.util.concurrent.Executors.newFixedThreadPool(jobs)
    implicit val ec: ExecutionContext = ExecutionContext.fromExecutor(pool)
    try {
      val us = units(sv, top)
      val futures = us.map { case (label, m, bb) =>
        val text = AccelArea.subtree(mods, m).filterNot(x =>
          bb.exists(b => x.name != b && AccelArea.subtree(mods, b).exists(_.name == x.name))
        )
          .map(_.text).mkString
        label -> Future {
          val (a, p) = run(cacheDir, m.takeWhile(_ != '_'), text, m, bb, model = model)
          println(f"fmax: $label: ${p.summary}, ${model.pathNs(p.cells)}%.2f ns")
          Row(label, m, a, p, model.pathNs(p.cells))
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
      f"| ${r.unit} | ${r.area.lut}%,d | ${r.area.ff}%,d | ${r.area.dsp}%,d | ${r.area.bram36}%.1f | ${r.path.summary} | ${r.ns}%.2f | ${r.mhz}%.0f |"
    (Seq(
      "## Fmax estimate per unit (ESTIMATE)",
      "",
      f"Each unit synthesised alone (`synth_xilinx -family xc7`, then flattened; datapath units black-boxed in control units), the slower of two longest register-to-register paths by `ltp -noff t:FD* ... %%n` (by cell count, then with the carry chains cut too), cells on it turned into ns by the delay model *${model.name}* (docs/fmax.md) in $seconds%.0f s. Area here is per instance (the table above counts instances); the hierarchy is kept through mapping, so memories are distributed RAM, cut like registers, and LUT counts logic only. No placement or routing: an estimate, not a timing sign-off.",
      "",
      "| unit | LUT (logic) | FF | DSP48 | BRAM36 | path cells | ns | MHz |",
      "| --- | ---: | ---: | ---: | ---: | --- | ---: | ---: |"
    ) ++
      rows.map(line) ++
      Seq(
        "",
        f"Estimated system Fmax (slowest unit, **${worst.unit}**): **${worst.mhz}%.0f MHz** (${worst.ns}%.2f ns).",
        ""
      )).mkString("\n")
  }
}
