package rtaccel.sweep

import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.bvh.BvhLayout
import rtaccel.{AccelConfig, BoxTest}

import java.nio.file.{Path, Paths}

/** One point of `make speed-vs-error`: a hardware configuration (node
  * layout, box format, triangle format, box rounding, triangle test, box
  * test) and the compiled runs it is measured on. Every value is checked here, with a
  * message naming it.
  */
final case class SweepArgs(
    layout: BvhLayout,
    boxFmt: FloatFormat,
    triFmt: FloatFormat,
    rounding: BoxRounding,
    test: TriangleTest,
    /** How child boxes are tested: FP32 box lanes, or (4q/8q) in the node's grid. */
    boxTest: BoxTest,
    sweep: Path,
    /** Package names under `sweep/packages/` to measure error on (every ray, golden model). */
    runs: Seq[String],
    /** Of those, the runs also simulated in RTL for speed (first `speedRays` rays). */
    speedRuns: Seq[String],
    speedRays: Int,
    hardDir: Path,
    bridge: Path,
    threads: Int,
    seed: Long,
    /** Which group of runs this job measures; "" writes `<name>.json`, else `<name>.<group>.json`. */
    group: String
) {
  def dp: FloatDatapath = FloatDatapath(boxFmt, triFmt, test, rounding)

  /** `4q-e8m10-e8m23-cons-wt` (`-grid` after it for grid box tests): the point's name in file names and reports. */
  def name: String = SweepArgs.pointName(layout, boxFmt, triFmt, rounding, test, boxTest)

  /** The generic ZC706 configuration in this point's layout, box test and formats. */
  def config: AccelConfig = dp.configure(AccelConfig.zc706.copy(layout = layout, boxTest = boxTest))

  /** Packages are compiled once per layout: `<sweep>/packages/<layout>/<run>`. */
  def packageDir(run: String): Path = sweep.resolve("packages").resolve(layout.name).resolve(run)
  def hitsFile(run: String): Path = sweep.resolve("hits").resolve(name).resolve(s"$run.csv")
  def pointFile: Path = sweep.resolve("points").resolve(if (group.isEmpty) s"$name.json" else s"$name.$group.json")
}

object SweepArgs {
  def pointName(
      layout: BvhLayout,
      box: FloatFormat,
      tri: FloatFormat,
      r: BoxRounding,
      t: TriangleTest,
      boxTest: BoxTest = BoxTest.Fp32
  ): String =
    s"${layout.name}-${box.name}-${tri.name}-${r.tag}-${t.tag}${if (boxTest == BoxTest.Grid) "-grid" else ""}"

  val usage: String =
    "usage: SweepPoint --bvh 4|8|4q|8q|nori --box-float e8m10 --tri-float e8m23 (or --float for both) --rounding rne|conservative --triangle moller|watertight --sweep DIR " +
      "--runs a,b,... [--box-test fp32|grid] [--speed-runs a,b] [--speed-rays 1024] [--hard-dir scenes/hard] [--bridge PATH] [--threads 1] [--seed 1] [--group NAME]"

  def parse(args: Seq[String]): SweepArgs = {
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    val kv = args.grouped(2).map(p => p(0) -> p(1)).toMap
    val known = Set(
      "--bvh",
      "--float",
      "--box-float",
      "--tri-float",
      "--rounding",
      "--triangle",
      "--box-test",
      "--sweep",
      "--runs",
      "--speed-runs",
      "--speed-rays",
      "--hard-dir",
      "--bridge",
      "--threads",
      "--seed",
      "--group"
    )
    kv.keys.filterNot(known).foreach(k => fail(s"unknown option '$k'"))
    def req(k: String) = kv.getOrElse(k, fail(s"$k is required"))
    def list(k: String) = kv.get(k).toSeq.flatMap(_.split(',').map(_.trim).filter(_.nonEmpty))
    def int(k: String, default: Int) =
      kv.get(k).fold(default)(v => v.toIntOption.filter(_ >= 1).getOrElse(fail(s"$k: '$v' is not a whole number >= 1")))
    def wrap[A](k: String)(f: => A): A =
      try f
      catch { case e: IllegalArgumentException => fail(s"$k: ${e.getMessage}") }
    val runs = list("--runs")
    if (runs.isEmpty) fail("--runs: give at least one package name")
    val speed = list("--speed-runs")
    speed.filterNot(runs.contains).foreach(r => fail(s"--speed-runs: '$r' is not among --runs"))
    def fmt(k: String) = wrap(k)(FloatFormat.parse(kv.getOrElse(k, req("--float"))))
    val a = SweepArgs(
      layout = wrap("--bvh")(BvhLayout.parse(kv.getOrElse("--bvh", "nori"))),
      boxFmt = fmt("--box-float"),
      triFmt = fmt("--tri-float"),
      rounding = wrap("--rounding")(BoxRounding.parse(req("--rounding"))),
      test = wrap("--triangle")(TriangleTest.parse(req("--triangle"))),
      boxTest = wrap("--box-test")(BoxTest.parse(kv.getOrElse("--box-test", "fp32"))),
      sweep = Paths.get(req("--sweep")),
      runs = runs,
      speedRuns = speed,
      speedRays = int("--speed-rays", 1024),
      hardDir = Paths.get(kv.getOrElse("--hard-dir", "scenes/hard")),
      bridge = Paths.get(kv.getOrElse("--bridge", "nori-bridge/target/release/nori-bridge")),
      threads = int("--threads", 1),
      seed = kv.get("--seed").fold(1L)(v => v.toLongOption.getOrElse(fail(s"--seed: '$v' is not a whole number"))),
      group = kv.getOrElse("--group", "").filter(c => c.isLetterOrDigit || c == '-')
    )
    // A grid box test needs a quantized layout and FP32 box constants: AccelConfig says which is missing.
    wrap("--box-test")(a.config)
    a
  }

  private def fail(why: String): Nothing = throw new IllegalArgumentException(s"$why\n$usage")
}
