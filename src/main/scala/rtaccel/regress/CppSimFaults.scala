package rtaccel.regress

import chisel3.Data
import rtaccel.scene.ScenePackage

import java.nio.file.{Files, Paths}
import scala.sys.process._

/** `make faults` (docs/faults.md): faults injected into the C++ simulation of
  * the board, and librtaccel's recovery. Builds the simulator of the
  * package's configuration (the one `make cppsim-test` builds, reused), builds
  * sw/sim/rtaccel_faults_main.cpp beside it, runs it (each fault, `--trials`
  * times: the faulted operation must end cleanly and the next batch must
  * return the reference batch's hits byte for byte; then librtaccel's bad
  * use), then checks the reference batch's hits ray by ray against the golden
  * model, so "byte for byte" means golden-exact.
  *
  * usage: CppSimFaults --package DIR --out DIR --rays N --trials N --seed N --report FILE
  */
object CppSimFaults {
  def main(args: Array[String]): Unit = {
    val ok = Cli.orExit(run(args.toSeq))
    sys.exit(if (ok) 0 else 1)
  }

  def run(args: Seq[String]): Boolean = {
    val kv = args.grouped(2).collect { case Seq(k, v) => k -> v }.toMap
    def need(k: String) = kv.getOrElse(k, throw new IllegalArgumentException(s"CppSimFaults: $k is required"))
    def count(k: String) =
      need(k).toIntOption.filter(_ >= 1).getOrElse(throw new IllegalArgumentException(s"CppSimFaults: $k '${kv(k)}'"))
    val pkgDir = Paths.get(need("--package"))
    if (!Files.exists(pkgDir.resolve("image.bin")))
      throw new IllegalArgumentException(
        s"$pkgDir/image.bin: no package (make it with nori-bridge compile, as mk/faults.mk does)"
      )
    val a = RegressArgs(pkgDir, Paths.get(need("--out")))
    val n = count("--rays")
    val trials = count("--trials")
    val seed = need("--seed").toLongOption.getOrElse(
      throw new IllegalArgumentException(s"CppSimFaults: --seed '${kv("--seed")}'")
    )
    val report = Paths.get(need("--report")).toAbsolutePath
    val pkg = ScenePackage.load(pkgDir)
    val rays = pkg.rays.take(n)
    val cfg = Regress.config(a, pkg)
    val chosen = DatapathChoice.resolve(RegressArgs.formats(a)._1, RegressArgs.formats(a)._2, a.triangle, a.rounding)
    Files.createDirectories(a.out)
    Files.createDirectories(report.getParent)
    chosen match {
      case c: Chosen[t, s] =>
        val cc = c.asInstanceOf[Chosen[Data, s]]
        val dir = CppSim.build(cfg, cc.dp)
        val built =
          Seq("make", "-s", "-C", "sw", "faults", s"SIMDIR=$dir", s"VSRC=${dir.resolve("rtaccel_system.sv")}").!
        if (built != 0) throw new IllegalStateException(
          s"faults: building rtaccel-faults in $dir failed (make -C sw faults, exit $built)"
        )
        val rc = Seq(
          dir.resolve("rtaccel-faults").toString,
          pkgDir.toAbsolutePath.toString,
          a.out.toAbsolutePath.toString,
          rays.size.toString,
          trials.toString,
          seed.toString,
          report.toString
        ).!
        val hits = CppSim.readHits(a.out.resolve("hits.bin"), rays.size)
        val bad = Regress.goldenCheck(cfg, pkg, rays, cc, hits)
        println(
          s"faults: the reference batch's ${rays.size} rays: ${bad.size} golden mismatches; rtaccel-faults exit $rc"
        )
        rc == 0 && bad.isEmpty
    }
  }
}
