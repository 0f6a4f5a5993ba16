package rtaccel.regress

import java.nio.file.{Files, Path}
import scala.sys.process._

/** Runs nori-bridge, the software half of the regression. */
object Bridge {
  private def exec(bridge: Path, args: Seq[String]): Unit = {
    if (!Files.isExecutable(bridge))
      throw new IllegalArgumentException(
        s"$bridge: nori-bridge is not built (run `make setup`, or `make test`, which builds it first)"
      )
    val cmd = bridge.toString +: args
    val rc = Process(cmd).!
    if (rc != 0) throw new IllegalArgumentException(s"`${cmd.mkString(" ")}` failed with exit code $rc")
  }

  /** Compiles a Nori scene into a package directory (rays: primary|shadow|ao|random|file), in BVH
    * layout `bvh` (nori-bridge's `--bvh`; None: its default).
    */
  def compile(
      bridge: Path,
      scene: Path,
      pkg: Path,
      rays: String,
      extra: Seq[String] = Nil,
      bvh: Option[String] = None
  ): Unit =
    exec(
      bridge,
      Seq("compile", scene.toString, "--out", pkg.toString, "--rays", rays) ++ bvh.toSeq.flatMap(
        Seq("--bvh", _)
      ) ++ extra
    )

  /** Compares `hits` (by default out/hits.csv) with the package's reference; writes and returns out/accuracy.json. */
  def compare(bridge: Path, pkg: Path, out: Path, precisionBits: Int, hits: Option[Path] = None): ujson.Value = {
    val acc = out.resolve("accuracy.json")
    Files.createDirectories(out)
    exec(
      bridge,
      Seq(
        "compare",
        "--package",
        pkg.toString,
        "--hits",
        hits.getOrElse(out.resolve("hits.csv")).toString,
        "--out",
        acc.toString,
        "--precision-bits",
        precisionBits.toString
      )
    )
    ujson.read(Files.readString(acc))
  }

  /** Scores a hits file against a hard case's expect.csv (scenes/hard/); returns the JSON it writes. */
  def hardScore(bridge: Path, pkg: Path, hits: Path, expect: Path, out: Path): ujson.Value = {
    Files.createDirectories(out.toAbsolutePath.getParent)
    exec(
      bridge,
      Seq(
        "hard-score",
        "--package",
        pkg.toString,
        "--hits",
        hits.toString,
        "--expect",
        expect.toString,
        "--out",
        out.toString
      )
    )
    ujson.read(Files.readString(out))
  }

  /** nori-bridge judges whole packages; a run of the first `n` rays is judged
    * on a copy of the package holding just those rays and their reference
    * rows (rays.csv and reference.csv list one ray per line, in order, after
    * a header). Returns the copy's directory.
    */
  def firstRays(pkg: Path, n: Int, dir: Path): Path = {
    Files.createDirectories(dir)
    for (f <- Seq("image.bin", "scene.json", "package.json"))
      Files.copy(pkg.resolve(f), dir.resolve(f), java.nio.file.StandardCopyOption.REPLACE_EXISTING)
    for (f <- Seq("rays.csv", "reference.csv")) {
      val lines = Files.readAllLines(pkg.resolve(f))
      Files.write(dir.resolve(f), lines.subList(0, (n + 1).min(lines.size)))
    }
    dir
  }

  /** PNGs for camera rays; other ray kinds have no image, and nothing is drawn. */
  def render(bridge: Path, pkg: Path, out: Path): Option[Path] = {
    val manifest = ujson.read(Files.readString(pkg.resolve("package.json")))
    if (manifest.obj.get("ray_kind").map(_.str).contains("primary")) {
      exec(
        bridge,
        Seq("render", "--package", pkg.toString, "--hits", out.resolve("hits.csv").toString, "--out-dir", out.toString)
      )
      Some(out.resolve("diff.png"))
    } else None
  }
}
