package rtaccel.tools

import chisel3.RawModule

import java.nio.file.{Files, Path}
import scala.sys.process._

/** SystemVerilog emission and Yosys synthesis, shared by every area report. */
object Synth {

  /** Yosys 0.23 rejects firtool's `automatic logic` locals and packed arrays. */
  val firtoolOpts: Array[String] = Array(
    "--lowering-options=disallowLocalVariables,disallowPackedArrays",
    "-disable-all-randomization",
    "-strip-debug-info"
  )

  def emit(gen: => RawModule): String =
    _root_.circt.stage.ChiselStage.emitSystemVerilog(gen, firtoolOpts = firtoolOpts)

  /** Xilinx 7-series cell counts. BRAM is in RAMB36 equivalents (two RAMB18 = one).
    *
    * `lut` counts LUTs used as logic; `lutram` the LUT sites that hold distributed
    * RAM (by cell type, [[Synth.lutramSites]]) and `srl` the shift registers (one
    * LUT each). Both kinds of memory take SLICEM LUTs out of the device's LUT
    * count, so [[lutSites]] (what Vivado reports as Slice LUTs) is what must fit.
    */
  final case class Area(lut: Int, ff: Int, srl: Int, dsp: Int, carry: Int, ramb36: Int, ramb18: Int, lutram: Int) {
    def +(o: Area): Area = Area(
      lut + o.lut,
      ff + o.ff,
      srl + o.srl,
      dsp + o.dsp,
      carry + o.carry,
      ramb36 + o.ramb36,
      ramb18 + o.ramb18,
      lutram + o.lutram
    )
    def bram36: Double = ramb36 + ramb18 / 2.0

    /** LUTs used as memory: distributed RAM and shift registers (SLICEM LUTs only). */
    def lutMemory: Int = lutram + srl

    /** Every LUT used, as logic or as memory. */
    def lutSites: Int = lut + lutMemory
  }
  val zero: Area = Area(0, 0, 0, 0, 0, 0, 0, 0)

  /** LUT sites per distributed-RAM primitive (UG474, 7 Series CLB user guide: a
    * 64 x 1 single-port RAM is one LUT6, a dual-port one two, a quad-port
    * RAM32M/RAM64M all four LUTs of a SLICEM, RAM128X1S two, RAM128X1D and
    * RAM256X1S four). A primitive not listed fails the count, never counts as 0.
    */
  val lutramSites: Map[String, Int] = Map(
    "RAM32X1S" -> 1,
    "RAM64X1S" -> 1,
    "RAM32X1D" -> 2,
    "RAM64X1D" -> 2,
    "RAM128X1S" -> 2,
    "RAM32M" -> 4,
    "RAM64M" -> 4,
    "RAM128X1D" -> 4,
    "RAM256X1S" -> 4
  )

  private def isLutram(c: String) = c.startsWith("RAM") && !c.startsWith("RAMB")

  private def areaOf(counts: Seq[(String, Int)], file: Path): Area = {
    def sum(p: String => Boolean) = counts.collect { case (c, n) if p(c) => n }.sum
    counts.collect { case (c, _) if isLutram(c) && !lutramSites.contains(c) => c }.foreach(c =>
      throw new IllegalArgumentException(s"$file: distributed RAM cell $c has no LUT count in Synth.lutramSites")
    )
    Area(
      lut = sum(_.matches("LUT[1-6].*")),
      ff = sum(_.matches("FD[A-Z_0-9]*")),
      srl = sum(_.startsWith("SRL")),
      dsp = sum(_.startsWith("DSP48")),
      carry = sum(_ == "CARRY4"),
      ramb36 = sum(_.startsWith("RAMB36")),
      ramb18 = sum(_.startsWith("RAMB18")),
      lutram = counts.collect { case (c, n) if isLutram(c) => n * lutramSites(c) }.sum
    )
  }
  private val cellLine = """(?m)^\s+(\w+)\s+(\d+)\s*$""".r

  /** The whole design's cells: the last `Number of cells` block of `stat` (the hierarchy total). */
  def parseTotal(log: String, file: Path): Area = {
    val block = log.lastIndexOf("Number of cells:")
    require(block >= 0, s"$file: no 'Number of cells' in the Yosys log")
    areaOf(cellLine.findAllMatchIn(log.substring(block)).map(m => m.group(1) -> m.group(2).toInt).toSeq, file)
  }

  /** Runs `synth_xilinx -family xc7` on `top` from `sv`, logging beside it
    * (by default as `<top>.yosys.log`; give `log` when several runs share a directory and a top).
    * The hierarchy is kept unless `flatten` (see [[FmaxEstimate.script]] for what that does to memories).
    */
  def yosys(
      sv: Path,
      top: String,
      blackboxes: Seq[String] = Nil,
      log0: Option[Path] = None,
      flatten: Boolean = false
  ): Area = {
    val log = log0.getOrElse(sv.resolveSibling(s"$top.yosys.log"))
    val bb = if (blackboxes.isEmpty) "" else s"blackbox ${blackboxes.mkString(" ")}; "
    val script =
      s"read_verilog -sv $sv; ${bb}synth_xilinx -family xc7${if (flatten) " -flatten" else ""} -top $top; stat"
    val rc = Seq("yosys", "-q", "-l", log.toString, "-p", script).!(ProcessLogger(_ => ()))
    require(rc == 0, s"yosys failed on $top from $sv (exit $rc); see $log")
    parseTotal(Files.readString(log), log)
  }

  /** Module names defined in an emitted file, in order. */
  def modules(sv: String): Seq[String] = """(?m)^module (\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq
}
