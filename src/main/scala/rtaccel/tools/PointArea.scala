package rtaccel.tools

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.{AccelConfig, BoxTest, RtAccel}

import java.nio.file.{Files, Paths}

/** The cost axis of one `make speed-vs-error` point: Yosys xc7 area of the
  * whole generic ZC706 accelerator (AccelConfig.zc706's ray IDs and stack) in one
  * configuration, per unit and in total, and how many instances fit on the
  * ZC706. One command line per point:
  *
  *   PointArea --bvh 4q --box-float e8m10 --tri-float e8m23 --rounding conservative --triangle watertight
  *             --out build/sweep/area/4q-e8m10-e8m23-cons-wt.json [--cache build/area-cache] [--jobs 1]
  *             [--box-test fp32|grid]
  *
  * (`--float` sets both formats.) `box_lanes` is the K box lanes together (with `--box-test grid`,
  * the grid unit: its FP32 node stage and K integer lanes).
  */
object PointArea {
  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val usage =
      "usage: PointArea [--bvh nori|2|4|8|4q|8q] --box-float e8m10 --tri-float e8m23 (or --float e8m12) --rounding rne|conservative --triangle moller|watertight --out FILE [--cache DIR] [--jobs N] [--box-test fp32|grid]"
    def req(k: String) = kv.getOrElse(k, { System.err.println(s"Error: $k is required\n$usage"); sys.exit(2) })
    val t0 = System.nanoTime()
    def fmt(k: String) = FloatFormat.parse(kv.getOrElse(k, req("--float")))
    val (dp, layout) =
      try (
          FloatDatapath(
            fmt("--box-float"),
            fmt("--tri-float"),
            TriangleTest.parse(req("--triangle")),
            BoxRounding.parse(req("--rounding"))
          ),
          rtaccel.bvh.BvhLayout.parse(kv.getOrElse("--bvh", "nori"))
        )
      catch { case e: IllegalArgumentException => System.err.println(s"Error: ${e.getMessage}\n$usage"); sys.exit(2) }
    val out = Paths.get(req("--out"))
    // The point's node layout sets the box lanes (K) and the node decode; the box test, their kind.
    val cfg =
      try dp.configure(
          AccelConfig.zc706.copy(layout = layout, boxTest = BoxTest.parse(kv.getOrElse("--box-test", "fp32")))
        )
      catch { case e: IllegalArgumentException => System.err.println(s"Error: ${e.getMessage}\n$usage"); sys.exit(2) }
    val sv = Synth.emit(new RtAccel(cfg, dp))
    val top = Synth.modules(sv).last
    val rows = AccelArea.measure(
      sv,
      top,
      dp.name,
      Paths.get(kv.getOrElse("--cache", "build/area-cache")),
      kv.getOrElse("--jobs", "1").toInt
    )
    val total = AccelArea.total(rows)
    // `lut` counts every LUT used, as logic or as memory, as make verilog's table does; `lutram` the LUTs used as
    // memory among them.
    def obj(a: Synth.Area) = ujson.Obj(
      "lut" -> a.lutSites,
      "ff" -> a.ff,
      "dsp" -> a.dsp,
      "bram36" -> a.bram36,
      "carry" -> a.carry,
      "lutram" -> a.lutMemory
    )
    val js = obj(total)
    js("config") = out.getFileName.toString.stripSuffix(".json")
    js("datapath") = dp.name
    js("instances_zc706") = AccelArea.instances(total, EmitVerilog.Zc706)
    js("units") = ujson.Obj.from(rows.map { case (u, a) => u -> obj(a) })
    // measure's BoxLane row counts every instance: all K lanes.
    rows.find(r => r._1 == "BoxLane" || r._1 == AccelArea.gridBoxUnit).foreach { case (_, a) =>
      js("box_lanes") = obj(a)
    }
    js("layout") = layout.name
    js("seconds") = (System.nanoTime() - t0) / 1e9
    Files.createDirectories(out.toAbsolutePath.getParent)
    Files.writeString(out, ujson.write(js, indent = 2))
    println(s"area ${dp.name}: $total, ${js("instances_zc706").num.toInt} instances on the ZC706 -> $out")
  }
}
