package rtaccel.datapath

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FloatFormat
import rtaccel.datapath.KernelVectors.hex

/** The golden models against the HLS twins' FP32 RNE outputs (every line of
  * the hls/build/vectors .out files, inputs and outputs bit for bit, plus the per-ray
  * columns rcp and kx ky kz Sx Sy Sz on every valid ray).
  */
class FloatGoldenSpec extends AnyFlatSpec {
  private val f32 = FloatFormat.FP32
  private def dp(t: TriangleTest, r: BoxRounding) = FloatGolden(FloatDatapath(f32, t, r))

  private def mismatches[E](cases: Seq[KernelCase])(got: KernelCase => E, want: KernelCase => E): Seq[String] =
    cases.iterator.flatMap { c =>
      val (g, w) = (got(c), want(c))
      if (g == w) None else Some(s"${c.where}: golden $g, HLS $w")
    }.take(10).toSeq

  "the FP32 RNE box golden model" should "match bbox.out bit for bit on every line, rcp included" in {
    val cases = KernelVectors.bboxOutFile
    val g = dp(TriangleTest.Moller, BoxRounding.Nearest)
    val bad = mismatches(cases)(GoldenRun.box(g, _), GoldenRun.boxOf)
    assert(bad.isEmpty, bad.mkString("\n"))
    val rcpBad = mismatches(cases.filter(c => !GoldenRun.boxOf(c).err))(
      { c =>
        val (k, _) = g.setup(c.o, c.d, c.tmin, c.tmax)
        k.box.rcpLo.indices.map(i => hex(if (f32.sign(k.box.d(i))) f32.negate(k.box.rcpLo(i)) else k.box.rcpLo(i)))
      },
      c => c.in.slice(14, 17).map(hex)
    )
    assert(rcpBad.isEmpty, rcpBad.mkString("\n"))
    info(s"${cases.size} cases")
  }

  "the FP32 Moller-Trumbore golden model" should "match prim_mt.out bit for bit on every line" in {
    val cases = KernelVectors.mtOutFile
    val g = dp(TriangleTest.Moller, BoxRounding.Nearest)
    val bad = mismatches(cases)(GoldenRun.prim(g, _), GoldenRun.primOf)
    assert(bad.isEmpty, bad.mkString("\n"))
    info(s"${cases.size} cases")
  }

  // Conservative mode computes Sz by its own division; the e8m23_wt_cons
  // hardware run checks it against prim_wt.out (FloatDatapathSpec).
  for (r <- Seq(BoxRounding.Nearest)) {
    s"the FP32 watertight golden model (box $r)" should "match prim_wt.out bit for bit, shear included" in {
      val cases = KernelVectors.wtOutFile
      val g = dp(TriangleTest.Watertight, r)
      val bad = mismatches(cases)(GoldenRun.prim(g, _), GoldenRun.primOf)
      assert(bad.isEmpty, bad.mkString("\n"))
      val shearBad = mismatches(cases.filter(c => !GoldenRun.primOf(c).err))(
        { c =>
          val s = g.setup(c.o, c.d, c.tmin, c.tmax)._1.tri.shear.get
          def axis(oh: Seq[Boolean]) = BigInt(oh.indexOf(true))
          Seq(axis(s.kx), axis(s.ky), axis(s.kz), s.sx, s.sy, s.sz).map(hex)
        },
        c => c.in.slice(17, 23).map(hex)
      )
      assert(shearBad.isEmpty, shearBad.mkString("\n"))
      info(s"${cases.size} cases")
    }
  }
}
