package rtaccel.tools

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.{AccelConfig, RtAccel}

import java.nio.file.{Files, Paths}

/** The cost axis of one `make speed-vs-error` point: Yosys xc7 area of the
  * whole generic ZC706 accelerator (64 ray IDs, stack 32) in one
  * configuration, per unit and in total, and how many instances fit on the
  * ZC706. One command line per point:
  *
  *   PointArea --float e8m12 --rounding rne --triangle watertight --out build/sweep/area/e8m12-rne-wt.json
  *             [--cache build/area-cache] [--jobs 1]
  */
object PointArea {
  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val usage = "usage: PointArea --float e8m12 --rounding rne|conservative --triangle moller|watertight --out FILE [--cache DIR] [--jobs N]"
    def req(k: String) = kv.getOrElse(k, { System.err.println(s"Error: $k is required\n$usage"); sys.exit(2) })
    val t0 = System.nanoTime()
    val dp = try FloatDatapath(FloatFormat.parse(req("--float")), TriangleTest.parse(req("--triangle")), BoxRounding.parse(req("--rounding")))
    catch { case e: IllegalArgumentException => System.err.println(s"Error: ${e.getMessage}\n$usage"); sys.exit(2) }
    val out = Paths.get(req("--out"))
    // The sweep's packages use nori-bridge's default layout (nori), so its area is that hardware's.
    val cfg = AccelConfig.zc706.copy(float = dp.fmt, layout = rtaccel.BvhLayout.Nori)
    val sv = Synth.emit(new RtAccel(cfg, dp))
    val top = Synth.modules(sv).last
    val rows = AccelArea.measure(sv, top, dp.name, Paths.get(kv.getOrElse("--cache", "build/area-cache")), kv.getOrElse("--jobs", "1").toInt)
    val total = AccelArea.total(rows)
    def obj(a: Synth.Area) = ujson.Obj("lut" -> a.lut, "ff" -> a.ff, "dsp" -> a.dsp, "bram36" -> a.bram36, "carry" -> a.carry, "lutram" -> a.lutram)
    val js = obj(total)
    js("config") = out.getFileName.toString.stripSuffix(".json")
    js("datapath") = dp.name
    js("instances_zc706") = AccelArea.instances(total, EmitVerilog.Zc706)
    js("units") = ujson.Obj.from(rows.map { case (u, a) => u -> obj(a) })
    js("seconds") = (System.nanoTime() - t0) / 1e9
    Files.createDirectories(out.toAbsolutePath.getParent)
    Files.writeString(out, ujson.write(js, indent = 2))
    println(s"area ${dp.name}: $total, ${js("instances_zc706").num.toInt} instances on the ZC706 -> $out")
  }
}
