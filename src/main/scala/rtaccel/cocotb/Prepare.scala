package rtaccel.cocotb

import rtaccel.AccelConfig
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.regress.Cli
import rtaccel.scene.ScenePackage
import rtaccel.system.{RegisterMap, RtAccelSystem, SystemConfig}
import rtaccel.tools.Synth

import java.nio.file.{Files, Path, Paths}

/** `make test-cocotb`'s inputs, in one sbt call: for each core count, the
  * Verilog of rtaccel_system and a config.json for the bench
  * (src/test/cocotb), and per ray set the golden hits (GoldenCsv). One core
  * configuration for all: FP32 watertight with conservative boxes (the
  * system's default arithmetic), few ray IDs, sized to the packages' scene.
  *
  * Usage: Prepare --out build/cocotb --cores 1,2 --packages <primary pkg>,<shadow pkg> [--ids 8]
  */
object Prepare {

  /** Node store small enough (4 of the Cornell box's 8 four-wide nodes) that the deeper nodes come from DDR:
    * the bench covers both the store and the miss path.
    */
  val NodeStoreBytes = 512

  /** Triangle store likewise: 16 of the Cornell box's 32 triangles (2,048 bytes) on chip, the rest from DDR. */
  val TriStoreBytes = 1024

  def main(args: Array[String]): Unit = Cli.orExit {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    def need(k: String) = kv.getOrElse(k, throw new IllegalArgumentException(s"Prepare: $k is required"))
    val out = Paths.get(kv.getOrElse("--out", "build/cocotb"))
    val cores = need("--cores").split(',').map(_.trim.toInt).toSeq
    val pkgs = need("--packages").split(',').map(p => ScenePackage.load(Paths.get(p.trim))).toSeq
    require(pkgs.size == 2, "Prepare: --packages <primary>,<shadow>")
    val Seq(primary, shadow) = pkgs
    require(
      primary.image.bytes.sameElements(shadow.image.bytes),
      s"Prepare: ${primary.dir} and ${shadow.dir} must share one image.bin"
    )
    val ids = kv.getOrElse("--ids", "8").toInt
    val core = primary.sized(AccelConfig(numRayIds = ids))
    val misfits = primary.misfits(core)
    require(misfits.isEmpty, s"Prepare: ${primary.dir} does not fit: ${misfits.mkString("; ")}")
    val dp = FloatDatapath.of(core, TriangleTest.Watertight, BoxRounding.Conservative)
    val golden = FloatGolden(dp)

    val goldenFiles = Map(
      "primary" -> (primary.rays: Seq[rtaccel.golden.RayRecord]),
      "shadow" -> (shadow.rays: Seq[rtaccel.golden.RayRecord]),
      "invalid" -> GoldenCsv.invalidRays(primary.rays)
    ).map { case (name, rays) =>
      val f = out.resolve(s"golden-$name.csv")
      GoldenCsv.write(f, core, primary.image, golden, rays)
      println(s"cocotb: $f (${rays.size} rays, golden model ${dp.name})")
      name -> f
    }

    for (n <- cores) {
      val sys = SystemConfig(core = core, cores = n, nodeStoreBytes = NodeStoreBytes, triStoreBytes = TriStoreBytes)
      val dir = out.resolve(s"n$n")
      Files.createDirectories(dir)
      val sv = Synth.emit(new RtAccelSystem(sys, dp))
      writeIfChanged(dir.resolve("rtaccel_system.sv"), sv)
      writeIfChanged(dir.resolve("config.json"), ujson.write(config(sys, dp, primary, shadow, goldenFiles), indent = 2))
      println(
        s"cocotb: $dir: rtaccel_system.sv ($n cores, ${core.numRayIds} ray IDs, stack ${core.stackDepth}, ${dp.name})"
      )
    }
  }

  private def abs(p: Path) = p.toAbsolutePath.normalize.toString

  private def config(
      sys: SystemConfig,
      dp: FloatDatapath,
      primary: ScenePackage,
      shadow: ScenePackage,
      golden: Map[String, Path]
  ): ujson.Value = ujson.Obj(
    "cores" -> sys.cores,
    "ray_ids" -> sys.core.numRayIds,
    "stack_depth" -> sys.core.stackDepth,
    "layout" -> sys.core.layout.code,
    "float_exp" -> sys.core.triFloat.expBits,
    "float_man" -> sys.core.triFloat.manBits,
    "node_store_bytes" -> sys.nodeStoreBytes,
    "tri_store_bytes" -> sys.triStoreBytes,
    "datapath" -> dp.name,
    "error_bits" -> rtaccel.ErrorFlags.width,
    "version" -> RegisterMap.Version.toInt,
    "error_names" -> ujson.Arr.from(RegisterMap.errorFlags.sortBy(_._1).map(_._2)),
    "scene_errors" -> ujson.Arr.from(RegisterMap.sceneErrors.map { case (c, n, _) => ujson.Arr(c, n) }),
    // The single source of the map, and the committed header a driver includes, checked against it.
    "registers" -> ujson.Obj.from(RegisterMap.regs.map { r =>
      r.name -> ujson.Obj(
        "offset" -> r.offset,
        "fields" -> ujson.Obj.from(r.fields.map(f => f.name -> ujson.Arr(f.lsb, f.width)))
      )
    }),
    "header" -> abs(Paths.get("sw/include/rtaccel_regs.h")),
    "packages" -> ujson.Obj(
      "primary" -> ujson.Obj("image" -> abs(primary.dir.resolve("image.bin"))),
      "shadow" -> ujson.Obj("image" -> abs(shadow.dir.resolve("image.bin")))
    ),
    "golden" -> ujson.Obj.from(golden.toSeq.sortBy(_._1).map { case (k, f) => k -> ujson.Str(abs(f)) })
  )

  /** Keeps the file's timestamp when nothing changed, so the Verilator build is reused. */
  private def writeIfChanged(f: Path, text: String): Unit =
    if (!Files.exists(f) || Files.readString(f) != text) Files.writeString(f, text)
}
