package rtaccel.regress

import chisel3.Data
import rtaccel.scene.ScenePackage

import java.nio.file.{Files, Paths}
import scala.sys.process._

/** `make cppsim-test` (part of `make test`): librtaccel against the Verilated
  * system. Builds the simulator of the package's configuration (one core),
  * runs sw/test/test_librtaccel.cpp (the driver sequence, the C++ wrapper, the
  * error paths), then checks every hit it read back, ray by ray, against the
  * golden model of the same hardware.
  *
  * usage: CppSimTest --package DIR --out DIR --rays N
  */
object CppSimTest {
  def main(args: Array[String]): Unit = {
    val ok = Cli.orExit(run(args.toSeq))
    sys.exit(if (ok) 0 else 1)
  }

  def run(args: Seq[String]): Boolean = {
    val kv = args.grouped(2).collect { case Seq(k, v) => k -> v }.toMap
    def need(k: String) = kv.getOrElse(k, throw new IllegalArgumentException(s"CppSimTest: $k is required"))
    val pkgDir = Paths.get(need("--package"))
    if (!Files.exists(pkgDir.resolve("image.bin")))
      throw new IllegalArgumentException(
        s"$pkgDir/image.bin: no package (make it with nori-bridge compile, as mk/cppsim.mk does)"
      )
    val a = RegressArgs(pkgDir, Paths.get(need("--out")))
    val n = need("--rays").toIntOption.filter(_ >= 1).getOrElse(throw new IllegalArgumentException(
      s"--rays '${kv("--rays")}'"
    ))
    val pkg = ScenePackage.load(pkgDir)
    val rays = pkg.rays.take(n)
    val cfg = Regress.config(a, pkg)
    val chosen = DatapathChoice.resolve(RegressArgs.formats(a)._1, RegressArgs.formats(a)._2, a.triangle, a.rounding)
    Files.createDirectories(a.out)
    chosen match {
      case c: Chosen[t, s] =>
        val cc = c.asInstanceOf[Chosen[Data, s]]
        val dir = CppSim.build(cfg, cc.dp)
        CppSim.linkTestSystem(dir)
        val rc = Seq(
          dir.resolve("test-librtaccel").toString,
          pkgDir.toAbsolutePath.toString,
          a.out.toAbsolutePath.toString,
          rays.size.toString
        ).!
        if (rc != 0) { println(s"cppsim-test: test-librtaccel failed (exit $rc)"); return false }
        val hits = CppSim.readHits(a.out.resolve("hits.bin"), rays.size)
        val bad = Regress.goldenCheck(cfg, pkg, rays, cc, hits)
        println(
          s"cppsim-test: ${rays.size} rays through librtaccel and the Verilated system, ${bad.size} golden mismatches"
        )
        bad.isEmpty
    }
  }
}
