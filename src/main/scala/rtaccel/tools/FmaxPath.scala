package rtaccel.tools

import java.nio.file.{Files, Path}

/** The longest path of one unit, net by net: `make fmax-path UNIT=<module> [SV=<design.sv>]`.
  *
  * [[FmaxEstimate]]'s table names a path's two ends and its cell count; this
  * prints every net bit along it with the cell that drives it and its arrival
  * time, which is what shows where a cut belongs. The unit is synthesised as
  * its row is (flattened, its datapath units black-boxed when it is a control
  * unit), uncached, and its netlist is kept beside the log.
  */
object FmaxPath {
  def main(args: Array[String]): Unit = {
    require(args.length == 2, "usage: FmaxPath <design.sv> <module or row label prefix>")
    val svFile = Path.of(args(0))
    require(Files.exists(svFile), s"$svFile: no such file (run make verilog first)")
    val sv = Files.readString(svFile)
    val top = Synth.modules(sv).last
    val mods = AccelArea.modules(sv)
    // The system's units as their rows are synthesised (SystemArea), then the core's (FmaxEstimate.units).
    val plans = SystemArea.plan(mods).map { case (_, m, text, bb) => (m, m, text, bb) } ++
      FmaxEstimate.units(sv, top).map { case (l, m, bb) => (l, m, FmaxEstimate.unitText(mods, m, bb), bb) }
    val (label, m, text, bb) = plans.find(_._2 == args(1)).orElse(plans.find(_._1.startsWith(args(1)))).getOrElse(
      throw new IllegalArgumentException(
        s"$svFile: no unit '${args(1)}'; units: ${plans.map(_._2).distinct.mkString(", ")}"
      )
    )
    val dir = Files.createDirectories(Path.of("build", "fmax-path"))
    val (_, _, netlist) = FmaxEstimate.synthesise(dir, m, text, m, bb, flatten = true)
    val model = DelayModel.zynq7
    val p = TimingGraph.longest(ujson.read(ujson.Readable.fromPath(netlist)), m, model)
    println(f"$label: ${p.ns}%.2f ns (${1000 / p.ns}%.0f MHz, an ESTIMATE by ${model.name})")
    println(f"${"arrival ns"}%10s  driver             net")
    for (s <- p.steps) println(f"${s.ns}%10.2f  ${s.driver}%-18s ${s.net}")
    println(s"ends at: ${p.to} (setup included in the total)")
    println(s"netlist: $netlist")
  }
}
