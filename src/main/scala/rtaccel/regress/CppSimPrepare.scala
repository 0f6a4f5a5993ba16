package rtaccel.regress

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.scene.{MemoryImage, ScenePackage}

import java.nio.file.{Files, Path, Paths}

/** The cold step of `make regress SIM=cpp` (scripts/regress-cpp.sh): emits
  * `rtaccel_system` for the configuration a regression asks for, builds
  * rtaccel-sim for it ([[CppSim.build]]), and writes what the JVM-free driver
  * needs to run it again into `--prepared DIR` (regress.json for the report, driver.env for the script): the
  * simulator's directory, rtaccel-sim's memory options, the hardware's
  * `configuration` block of stats.json, the node record size and whether the
  * C++ golden walk (nori-accel/golden/) is this hardware's golden model.
  * Later runs of the same configuration (warm) start no JVM.
  *
  * Usage: CppSimPrepare <the options of Regress> --prepared DIR
  */
object CppSimPrepare {
  def main(args: Array[String]): Unit = {
    val i = args.indexOf("--prepared")
    if (i < 0 || i + 1 >= args.length)
      Cli.orExit(throw new IllegalArgumentException("CppSimPrepare: --prepared DIR is required"))
    val dir = Paths.get(args(i + 1))
    Cli.orExit(prepare(RegressArgs.parse(args.toSeq.patch(i, Nil, 2)), dir))
  }

  /** The configuration nori-accel/golden/walk.cpp computes bit for bit (walk.h): FP32, watertight triangles,
    * conservative boxes, stack 64, leaves of at most 16 triangles, a layout of 32-byte slots.
    */
  def cppGoldenCovers(cfg: rtaccel.AccelConfig, dp: rtaccel.Datapath[_ <: chisel3.Data]): Boolean =
    dp == FloatDatapath(
      FloatFormat.FP32,
      FloatFormat.FP32,
      TriangleTest.parse("watertight"),
      BoxRounding.parse("conservative")
    ) &&
      cfg.stackDepth == 64 && cfg.maxLeafSize == 16 && !cfg.layout.quantized

  def prepare(a: RegressArgs, dir: Path): Unit = {
    val pkg = ScenePackage.load(a.pkg)
    val hw = Regress.hardware(a, pkg)
    val cfg = hw._1
    val chosen = hw._2
    val memory = CppSim.memoryOptions(a)
    val sim = CppSim.build(cfg, chosen.dp, clang = CppSim.useClang)
    Files.createDirectories(dir)
    val out = ujson.Obj(
      "simDir" -> sim.toString,
      "simOptions" -> ujson.Arr.from(memory),
      "goldenCpp" -> cppGoldenCovers(cfg, chosen.dp),
      "nodeBytes" -> pkg.image.nodeBytes.toDouble,
      "triBytes" -> rtaccel.leaf.TriangleRecord.RecordBytes.toDouble, // the bytes a triangle request reads
      "memoryKind" -> a.memoryKind.name,
      "precisionBits" -> (cfg.triFloat.manBits + 1),
      "configuration" -> Report.configuration(a, cfg, chosen.dp.name)
    )
    Files.writeString(dir.resolve("regress.json"), ujson.write(out, indent = 2))
    // The same for the driver script, which reads no JSON (sourced by scripts/regress-cpp.sh).
    Files.writeString(
      dir.resolve("driver.env"),
      Seq(
        s"sim_dir='$sim'",
        s"sim_options='${memory.mkString(" ")}'",
        s"golden=${if (cppGoldenCovers(cfg, chosen.dp)) "cpp" else "scala"}",
        s"precision_bits=${cfg.triFloat.manBits + 1}"
      ).mkString("", "\n", "\n")
    )
    println(s"cppsim: prepared $dir (simulator $sim)")
  }
}
