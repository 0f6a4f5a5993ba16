package rtaccel

import org.scalatest.flatspec.AnyFlatSpec

import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._

/** The test tree mirrors main: every Chisel module class in the hardware
  * packages has a spec of its own name in the mirrored folder
  * (`src/main/scala/rtaccel/system/HitDma.scala` ->
  * `src/test/scala/rtaccel/system/HitDmaSpec.scala`), or is listed below with
  * the reason it has none. A new module without a spec fails this check by name.
  */
class SpecsMirrorMainSpec extends AnyFlatSpec {
  behavior of "the test tree"

  /** The packages that hold hardware units. */
  private val packages = Seq("system", "traversal", "leaf", "fetch", "mem")

  /** Modules with no spec of their own, each with the reason. Keep it short. */
  private val allowed: Map[String, String] = Map(
    "BoxLane" -> ("abstract lane interface; its one implementation, FloatBox, is checked in datapath/FloatDatapathSpec " +
      "(through DatapathHarness) and inside traversal/BboxIntersectSpec"),
    "RayPrepUnit" -> ("abstract per-ray-constants interface; its one implementation, FloatRayPrep, is checked in " +
      "datapath/FloatDatapathSpec (through DatapathHarness) and inside fetch/FetchBVHSpec"),
    "GridLane" -> ("one child's grid box test, instantiated K times inside GridBboxIntersect; traversal/GridBboxIntersectSpec " +
      "checks every lane's answer bit for bit against GridLane.soft")
  )

  private val moduleClass = raw"""(?m)^\s*(?:abstract\s+|final\s+)?class\s+(\w+)[^\n{]*\bextends\s+(?:Raw)?Module\b""".r

  /** (package, class) of every Module or RawModule class declared in `pkg`. */
  private def modulesIn(pkg: String): Seq[(String, String)] = {
    val dir = Paths.get("src/main/scala/rtaccel", pkg)
    assert(Files.isDirectory(dir), s"$dir not found (run from the repository root)")
    Files.list(dir).iterator().asScala.toSeq.filter(_.toString.endsWith(".scala")).sortBy(_.toString).flatMap { f =>
      moduleClass.findAllMatchIn(Files.readString(f)).map(m => pkg -> m.group(1))
    }
  }

  private def specOf(pkg: String, name: String): Path = Paths.get("src/test/scala/rtaccel", pkg, s"${name}Spec.scala")

  it should "hold a <Unit>Spec for every module of system, traversal, leaf, fetch and mem" in {
    val modules = packages.flatMap(modulesIn)
    assert(modules.size >= 20, s"found only ${modules.size} modules: the scan is broken")
    val missing = modules.filterNot { case (pkg, name) => allowed.contains(name) || Files.exists(specOf(pkg, name)) }
    assert(
      missing.isEmpty,
      s"modules without a spec of their own name: ${missing.map { case (p, n) => s"$p/$n (want ${specOf(p, n)})" }.mkString(", ")}"
    )
  }

  it should "keep the allow-list to modules that exist and have no spec" in {
    val modules = packages.flatMap(modulesIn)
    val names = modules.map(_._2).toSet
    val stale = allowed.keys.filterNot(names.contains)
    assert(stale.isEmpty, s"allow-listed modules that no longer exist: ${stale.mkString(", ")}")
    val covered = modules.collect { case (p, n) if allowed.contains(n) && Files.exists(specOf(p, n)) => n }
    assert(
      covered.isEmpty,
      s"allow-listed modules that now have a spec (drop them from the list): ${covered.mkString(", ")}"
    )
  }
}
