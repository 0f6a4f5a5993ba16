package rtaccel.golden

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.regress.Bridge
import rtaccel.scene.{FloatText, ScenePackage}
import rtaccel.AccelConfig

import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._
import scala.sys.process._

/** nori-accel's C++ golden walk (nori-accel/golden/, which serves `make
  * render` and the Nori drop-in) against the RTL's golden model,
  * TraversalGolden in the configuration `make regress` generates by default
  * (FP32, watertight, conservative boxes, stack 64): every ray of every
  * regression scene and of the hard cases, bit for bit (t, u, v, prim, error
  * bits; shadow rays: occlusion and error bits, as the RTL is compared).
  * Needs nori-bridge built (make setup) and g++ (the spec runs `make -C nori-accel`).
  */
class NoriAccelGoldenSpec extends AnyFlatSpec {
  behavior of "nori-accel's golden walk"

  private val bridge = Paths.get("nori-bridge/target/release/nori-bridge")
  private val root = Paths.get("build/test-scenes")
  private val tool = Paths.get("nori-accel/build/golden-trace")

  private def compiled(scene: String, rays: String, layout: String, extra: Seq[String] = Nil): Path = {
    val name = Paths.get(scene).getFileName.toString.stripSuffix(".xml")
    val dir = root.resolve(s"$name-$rays-bvh$layout")
    Bridge.compile(bridge, Paths.get(scene), dir, rays, extra ++ Seq("--bvh", layout))
    dir
  }

  /** golden-trace's hits.csv rows as HitRecords (a miss: t = u = v = 0, prim 0, as TraversalGolden gives it). */
  private def cppHits(pkg: Path): IndexedSeq[HitRecord] = {
    val out = pkg.resolve("hits-nori-accel.csv")
    val rc = Seq(tool.toString, pkg.toString, out.toString).!
    assert(rc == 0, s"$tool $pkg failed (exit $rc)")
    Files.readAllLines(out).asScala.drop(1).toIndexedSeq.map { line =>
      val f = line.split(',')
      def bits(s: String) =
        FloatText.bits(FloatText.parse(s).getOrElse(throw new IllegalArgumentException(s"$out: '$line'")))
      if (f(1) == "1") HitRecord(f(0).toLong, hit = true, bits(f(2)), bits(f(3)), bits(f(4)), f(5).toLong, f(6).toInt)
      else HitRecord(f(0).toLong, hit = false, 0, 0, 0, 0, f(6).toInt)
    }
  }

  private def check(what: String, dir: Path): Unit = {
    val pkg = ScenePackage.load(dir)
    val cfg = AccelConfig.zc706.copy(layout = pkg.image.layout)
    val golden = FloatGolden(FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative))
    val cpp = cppHits(dir)
    assert(cpp.size == pkg.rays.size, s"$what: ${cpp.size} hits for ${pkg.rays.size} rays")
    var hits = 0
    for ((r, c) <- pkg.rays.zip(cpp)) {
      val e = TraversalGolden.trace(cfg, pkg.image, golden, r).hit
      assert(TraversalGolden.agrees(r, c, e), s"$what: ray ${r.number}: nori-accel $c, RTL golden $e")
      if (e.hit) hits += 1
    }
    println(s"nori-accel golden walk: $what: ${pkg.rays.size} rays ($hits hits) bit-exact with TraversalGolden")
    checked += dir
  }

  private val dropin = Paths.get("nori-accel/build/dropin-check")

  /** Every package checked here, for the drop-in's turn. */
  private val checked = scala.collection.mutable.ArrayBuffer.empty[Path]

  it should "build, with its directed roundings equal to the FPU's (make -C nori-accel test)" in {
    assert(Seq("make", "-s", "-C", "nori-accel", "test").! == 0, "make -C nori-accel test failed")
  }

  it should "answer every regression scene's rays bit for bit as the RTL's golden model, in every node layout" in {
    for (layout <- Seq("4", "nori", "8"))
      check(s"cornell primary bvh$layout", compiled("scenes/cornell-box/cornell-box.xml", "primary", layout))
    check("cornell shadow", compiled("scenes/cornell-box/cornell-box.xml", "shadow", "4"))
    check("cornell AO", compiled("scenes/cornell-box/cornell-box.xml", "ao", "4"))
    check("icosphere random", compiled("scenes/icosphere/icosphere.xml", "random", "4", Seq("--count", "3000")))
    check(
      "multi-mesh AO",
      compiled("scenes/multi-mesh/multi-mesh.xml", "ao", "4", Seq("--width", "40", "--height", "30"))
    )
    check(
      "multi-mesh primary bvh8",
      compiled("scenes/multi-mesh/multi-mesh.xml", "primary", "8", Seq("--width", "40", "--height", "30"))
    )
  }

  it should "answer the hard cases (scenes/hard/) bit for bit as the RTL's golden model" in {
    val hard = Paths.get("scenes/hard")
    val cases = Files.list(hard).iterator.asScala.filter(d => Files.exists(d.resolve("expect.csv"))).map(
      _.getFileName.toString
    ).toSeq.sorted
    assert(cases.nonEmpty, s"$hard has no hard cases: regenerate them with `make hard-cases`")
    for (c <- cases) {
      val dir = root.resolve(s"hard-$c")
      Bridge.compile(
        bridge,
        hard.resolve(c).resolve(s"$c.xml"),
        dir,
        hard.resolve(c).resolve("rays.txt").toString,
        Seq("--reference", "double", "--bvh", "4")
      )
      check(s"hard $c", dir)
    }
  }

  it should "give the same answers through the Nori drop-in (Accel::rayIntersect, several meshes) on every package above" in {
    assert(checked.nonEmpty, "the golden checks above did not run")
    val rc = (dropin.toString +: checked.map(_.toString).toSeq).!
    assert(rc == 0, s"$dropin found rays that differ from the golden walk (printed above)")
  }

  it should "record the rays Nori asks for as a rays.txt that nori-bridge compiles back to the same rays, bit for bit" in {
    val src = compiled("scenes/cornell-box/cornell-box.xml", "ao", "4")
    val txt = root.resolve("nori-accel-recorded-rays.txt")
    val rc = Process(Seq(dropin.toString, src.toString), None, "RTACCEL_RECORD" -> txt.toAbsolutePath.toString).!
    assert(rc == 0, s"$dropin $src failed")
    val replay = root.resolve("nori-accel-replay")
    Bridge.compile(bridge, Paths.get("scenes/cornell-box/cornell-box.xml"), replay, txt.toString, Seq("--bvh", "4"))
    val (a, b) = (ScenePackage.load(src).rays, ScenePackage.load(replay).rays)
    assert(a.size == b.size, s"recorded ${b.size} rays of ${a.size}")
    // rays.txt has no shadow column: the replay traces closest hits, whose occlusion answer is the same.
    for ((x, y) <- a.zip(b))
      assert(x.copy(shadow = false) == y.copy(shadow = false), s"ray ${x.number}: recorded $y, asked $x")
    println(s"nori-accel: ${a.size} rays recorded to $txt and compiled back bit for bit")
  }
}
