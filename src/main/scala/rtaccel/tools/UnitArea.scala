package rtaccel.tools

import java.nio.file.{Files, Path}

/** A few units, each synthesised alone (Yosys 0.23 `synth_xilinx -family
  * xc7` per top, flattened; cached in build/area-cache), as a markdown table
  * of area and longest register-to-register path by the delay model of
  * docs/fmax.md. Used by the `make grid-area` and
  * `make recip-area` pages.
  */
object UnitArea {

  /** One row per `(label, top, Verilog)`, each also printed with `tag`. */
  def table(tag: String, rows: Seq[(String, String, String)]): Seq[String] = {
    val model = DelayModel.zynq7
    Seq(
      "| unit | module | LUT | FF | DSP48 | CARRY4 | longest path | ns | MHz |",
      "|---|---|---:|---:|---:|---:|---|---:|---:|"
    ) ++ rows.map { case (label, top, sv) =>
      val (a, path) = FmaxEstimate.run(EmitVerilog.areaCache, tag, sv, top, Nil, model = model)
      val ns = path.ns
      println(f"$tag-area: $label: ${a.lut} LUT, ${a.ff} FF, ${a.dsp} DSP, ${path.described}, $ns%.2f ns")
      f"| $label | `$top` | ${a.lut}%,d | ${a.ff}%,d | ${a.dsp}%,d | ${a.carry}%,d | ${path.summary} | $ns%.2f | ${model.mhz(ns)}%.0f |"
    }
  }

  /** Writes `title`, the `intro` lines, the method and the table of `rows` to `out`, and prints it. */
  def write(out: Path, tag: String, title: String, intro: Seq[String], rows: Seq[(String, String, String)]): Unit = {
    val t0 = System.nanoTime()
    val lines = table(tag, rows)
    val md = (Seq(s"# $title", "") ++ intro ++ Seq(
      "Yosys 0.23 `synth_xilinx -family xc7` per top, flattened; longest path by the delay model:",
      f"${DelayModel.zynq7.name} (docs/fmax.md). ${(System.nanoTime() - t0) / 1e9}%.0f s.",
      ""
    ) ++ lines).mkString("\n") + "\n"
    Files.createDirectories(out.toAbsolutePath.getParent)
    Files.writeString(out, md)
    println(md)
  }
}
