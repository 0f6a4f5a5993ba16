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

  /** Xilinx 7-series cell counts. BRAM is in RAMB36 equivalents (two RAMB18 = one). */
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
  }
  val zero: Area = Area(0, 0, 0, 0, 0, 0, 0, 0)

  private def areaOf(counts: Seq[(String, Int)]): Area = {
    def sum(p: String => Boolean) = counts.collect { case (c, n) if p(c) => n }.sum
    Area(
      lut = sum(_.matches("LUT[1-6].*")),
      ff = sum(_.matches("FD[A-Z_0-9]*")),
      srl = sum(_.startsWith("SRL")),
      dsp = sum(_.startsWith("DSP48")),
      carry = sum(_ == "CARRY4"),
      ramb36 = sum(_.startsWith("RAMB36")),
      ramb18 = sum(_.startsWith("RAMB18")),
      lutram =
        sum(c => c.startsWith("RAM32") || c.startsWith("RAM64") || c.startsWith("RAM128") || c.startsWith("RAM256"))
    )
  }
  private val cellLine = """(?m)^\s+(\w+)\s+(\d+)\s*$""".r

  /** The whole design's cells: the last `Number of cells` block of `stat` (the hierarchy total). */
  def parseTotal(log: String, file: Path): Area = {
    val block = log.lastIndexOf("Number of cells:")
    require(block >= 0, s"$file: no 'Number of cells' in the Yosys log")
    areaOf(cellLine.findAllMatchIn(log.substring(block)).map(m => m.group(1) -> m.group(2).toInt).toSeq)
  }

  /** Runs `synth_xilinx -family xc7` on `top` from `sv` (hierarchy kept), logging beside it
    * (by default as `<top>.yosys.log`; give `log` when several runs share a directory and a top).
    */
  def yosys(sv: Path, top: String, blackboxes: Seq[String] = Nil, log0: Option[Path] = None): Area = {
    val log = log0.getOrElse(sv.resolveSibling(s"$top.yosys.log"))
    val bb = if (blackboxes.isEmpty) "" else s"blackbox ${blackboxes.mkString(" ")}; "
    val script = s"read_verilog -sv $sv; ${bb}synth_xilinx -family xc7 -top $top; stat"
    val rc = Seq("yosys", "-q", "-l", log.toString, "-p", script).!(ProcessLogger(_ => ()))
    require(rc == 0, s"yosys failed on $top from $sv (exit $rc); see $log")
    parseTotal(Files.readString(log), log)
  }

  /** Module names defined in an emitted file, in order. */
  def modules(sv: String): Seq[String] = """(?m)^module (\w+)""".r.findAllMatchIn(sv).map(_.group(1)).toSeq
}
