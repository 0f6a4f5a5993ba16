package rtaccel.datapath

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FloatFormat
import rtaccel.testutil.Seeded

/** Properties of every variant in FP32 and the narrow formats, on the golden
  * model (bit-exact with the hardware: FloatDatapathSpec), over every hard
  * case and a seeded sample of the .out files' inputs. Each case is checked
  * on its own; the first failures are named with file and line.
  */
class DatapathPropertySpec extends AnyFlatSpec {
  private val formats = FloatFormat.FP32 +: GoldenRun.narrowFormats
  private val sampleSize = 4000
  private lazy val boxFile = KernelVectors.bboxOutFile
  private lazy val triFile = KernelVectors.mtOutFile
  private def nonFiniteInput(c: KernelCase) = {
    val f = FloatFormat.FP32
    (c.o ++ c.d).exists(!f.isFinite(_)) || f.isNaN(c.tmin) || f.isNaN(c.tmax)
  }

  for (fmt <- formats; t <- TriangleTest.all; r <- BoxRounding.all) {
    val dp = FloatDatapath(fmt, t, r)
    dp.name should "never output NaN, miss on error rays and degenerate triangles, and give +0 on a miss" in
      Seeded(s"DatapathPropertySpec ${dp.name}") { rng =>
        val g = FloatGolden(dp)
        val bad = scala.collection.mutable.ArrayBuffer.empty[String]
        def fail(c: KernelCase, why: String) = if (bad.size < 10) bad += s"${c.where}: $why"
        var (exactHits, nearestMisses) = (0, 0)
        val boxes = KernelVectors.bboxHard ++ IndexedSeq.fill(sampleSize)(boxFile(rng.nextInt(boxFile.size)))
        for (c <- boxes) {
          val e = GoldenRun.box(g, c)
          if (fmt.isNaN(e.near)) fail(c, "NaN near")
          if (nonFiniteInput(c) && (!e.err || e.hit)) fail(c, s"NaN/inf ray: err ${e.err}, hit ${e.hit}")
          val (k, tmax) = g.setup(c.o, c.d, c.tmin, c.tmax)
          if (!k.box.err && ExactBox.hit(fmt, k.box.o, k.box.d, k.box.tmin, tmax, c.bmin, c.bmax).contains(true)) {
            exactHits += 1
            if (!e.hit) {
              if (r == BoxRounding.Conservative) fail(c, "false miss: the exact slab test hits")
              else nearestMisses += 1
            }
          }
        }
        val tris = KernelVectors.triHard ++ IndexedSeq.fill(sampleSize)(triFile(rng.nextInt(triFile.size)))
        for (c <- tris) {
          val e = GoldenRun.prim(g, c)
          if (Seq(e.t, e.u, e.v).exists(fmt.isNaN)) fail(c, s"NaN output $e")
          if (!e.hit && Seq(e.t, e.u, e.v).exists(_ != 0)) fail(c, s"miss with nonzero output $e")
          if (nonFiniteInput(c) && (!e.err || e.hit)) fail(c, s"NaN/inf ray: err ${e.err}, hit ${e.hit}")
          if (c.family.startsWith("zero_area") && e.hit) fail(c, "coincident-vertex triangle hit")
        }
        assert(bad.isEmpty, bad.mkString("\n"))
        info(
          s"${boxes.size} box, ${tris.size} triangle cases; $exactHits exact box hits, missed by this variant: $nearestMisses"
        )
      }
  }

  // Split formats (narrow conservative boxes, FP32 triangles): the box test must
  // enclose the exact slab test of the FP32 ray itself, the ray the triangle unit traces.
  for (box <- Seq(FloatFormat(8, 10), FloatFormat(6, 9), FloatFormat(5, 10))) {
    val dp = FloatDatapath(box, FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
    dp.name should "never miss a box the FP32 ray's exact slab test hits" in Seeded(
      s"DatapathPropertySpec ${dp.name}"
    ) { rng =>
      val g = FloatGolden(dp)
      val f32 = FloatFormat.FP32
      val bad = scala.collection.mutable.ArrayBuffer.empty[String]
      var exactHits = 0
      for (c <- KernelVectors.bboxHard ++ IndexedSeq.fill(sampleSize)(boxFile(rng.nextInt(boxFile.size)))) {
        val e = GoldenRun.box(g, c)
        if (box.isNaN(e.near) && bad.size < 10) bad += s"${c.where}: NaN near"
        val err32 = nonFiniteInput(c) || c.d.forall(f32.isZero)
        if (!err32 && ExactBox.hit(f32, c.o, c.d, c.tmin, c.tmax, c.bmin, c.bmax).contains(true)) {
          exactHits += 1
          if (!e.hit && !e.err && bad.size < 10) bad += s"${c.where}: false miss: the FP32 ray's exact slab test hits"
        }
      }
      assert(bad.isEmpty, bad.mkString("\n"))
      info(s"$exactHits exact FP32 box hits, none missed")
    }
  }

  /** Groups of consecutive hard-case lines with one family and one ray (docs/kernels.md section 7). */
  private def groups(cases: Seq[KernelCase]): Seq[Seq[KernelCase]] =
    cases.filter(_.family.startsWith("shared_")).foldLeft(List.empty[List[KernelCase]]) {
      case (g :: rest, c) if g.head.family == c.family && g.head.in.take(8) == c.in.take(8) => (c :: g) :: rest
      case (acc, c)                                                                         => List(c) :: acc
    }.reverse.map(_.reverse)

  for (fmt <- formats) {
    // Narrowing moves the ray off the exact edge point by up to an ulp; at
    // offsets 1e4/1e6 and scale 1e-6 that is larger than the group's patch in
    // a narrow format, so only the offset-0 groups are meaningful there.
    val families = if (fmt == FloatFormat.FP32) "shared_.*" else "shared_(edge|vertex)"
    s"watertight ${fmt.name}" should s"hit at least one triangle of every $families hard-case group" in {
      val g = FloatGolden(FloatDatapath(fmt, TriangleTest.Watertight, BoxRounding.Nearest))
      val gs = groups(KernelVectors.triHard).filter(_.head.family.matches(families))
      assert(gs.nonEmpty)
      val leaks = gs.filterNot(_.exists(c => GoldenRun.prim(g, c).hit))
      assert(leaks.size == 0, leaks.map(_.head.where).mkString("leaking groups:\n", "\n", ""))
      info(s"${gs.size} groups, no leak")
    }
  }
}
