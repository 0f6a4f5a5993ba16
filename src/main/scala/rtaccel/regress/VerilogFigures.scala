package rtaccel.regress

import java.nio.file.{Files, Path}

/** What `make verilog` wrote into build/verilog/resources.md that `make bench`
  * needs: the cores that fit on the xc7z045 and the estimated system Fmax
  * (rtaccel.tools.ResourceTable and FmaxEstimate.markdown). Read, never
  * hard-coded: the Fmax moves whenever the FP units are re-pipelined.
  */
final case class VerilogFigures(title: String, coresFit: Int, fmaxNs: Double, slowestUnit: String) {
  def fmaxMhz: Double = 1000.0 / fmaxNs
}

object VerilogFigures {
  // The system's own lines (cores beside MemoryFabric, the node store, the DMAs and the registers; the
  // slowest unit of core and system) when make verilog built the system top; else the core's alone.
  private val systemFitsRe =
    """Cores that fit beside the system's own units \(by the scarcest resource\): \*\*(\d+)\*\*""".r
  private val systemFmaxRe =
    """\*\*Estimated Fmax of the system\*\* \(its slowest unit, core or system, \*\*(.+?)\*\*\): \*\*[\d.]+ MHz\*\* \(([\d.]+) ns\)""".r
  private val fitsRe = """Instances that fit on the device \(by its scarcest resource\): \*\*(\d+)\*\*""".r
  private val nodeStoreRe = """Node store: (\d+) KiB""".r
  private val fmaxRe = """Estimated system Fmax \(slowest unit, \*\*(.+?)\*\*\): \*\*[\d.]+ MHz\*\* \(([\d.]+) ns\)""".r

  private val how = "run `make verilog` (the default ZC706 configuration, with synthesis) first"
  private def load(path: Path): String = {
    if (!Files.exists(path)) throw new IllegalArgumentException(s"$path: missing; $how")
    Files.readString(path)
  }

  /** Parses `path`; `expect` are words the title must hold (the configuration the bench simulates), and
    * `nodeStoreKib` the node store its system section must name, when it has one (the system the bench builds). */
  def read(path: Path, expect: Seq[String], nodeStoreKib: Option[Int] = None): VerilogFigures = {
    val text = load(path)
    val title = text.linesIterator.find(_.startsWith("# Resources: ")).map(_.stripPrefix("# Resources: "))
      .getOrElse(throw new IllegalArgumentException(s"$path: no '# Resources:' title line; $how"))
    val missing = expect.filterNot(title.contains)
    if (missing.nonEmpty)
      throw new IllegalArgumentException(
        s"$path: made for '$title', not the bench's configuration (no ${missing.mkString(", ")}); $how"
      )
    val fits = systemFitsRe.findFirstMatchIn(text).orElse(fitsRe.findFirstMatchIn(text)).map(_.group(1).toInt)
      .getOrElse(throw new IllegalArgumentException(s"$path: no 'Instances that fit on the device' line; $how"))
    val (unit, ns) = systemFmaxRe.findFirstMatchIn(text).orElse(fmaxRe.findFirstMatchIn(text)).map(m =>
      (m.group(1), m.group(2).toDouble)
    )
      .getOrElse(throw new IllegalArgumentException(
        s"$path: no 'Estimated system Fmax' line (the Fmax estimate); $how"
      ))
    if (fits < 1) throw new IllegalArgumentException(s"$path: $fits instances fit: nothing to simulate")
    // The system section names its node store (SystemArea.markdown).
    for (wantKib <- nodeStoreKib; kib <- nodeStoreRe.findFirstMatchIn(text).map(_.group(1).toInt) if kib != wantKib)
      throw new IllegalArgumentException(
        s"$path: made with a $kib KiB node store, not the $wantKib KiB this run builds (NODE_STORE_KIB); " +
          "run `make verilog` with the same NODE_STORE_KIB first"
      )
    VerilogFigures(title, fits, ns, unit)
  }

  // The system section's row of its cores' area (SystemArea.markdown): LUT, FF, DSP48, then BRAM36.
  private val coresRowRe = """\| (\d+) x core \(table above\) \| [\d,]+ \| [\d,]+ \| [\d,]+ \| ([\d.]+) \|""".r

  /** BRAM36 of one core (its ray stacks, ray buffer and per-ray tables), from the system section of `path`: what
    * every core takes from the device's block RAM beside the stores. */
  def coreBram36(path: Path): Double =
    coresRowRe.findFirstMatchIn(load(path)).map(m => m.group(2).toDouble / m.group(1).toInt).getOrElse(
      throw new IllegalArgumentException(s"$path: no '| N x core (table above) |' row (the system top's); $how")
    )
}
