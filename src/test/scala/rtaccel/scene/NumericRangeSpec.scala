package rtaccel.scene

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.fp.FloatFormat
import rtaccel.golden.RayRecord

/** Exponent sizing from a scene's numeric range (hardware sized to the scene). */
class NumericRangeSpec extends AnyFlatSpec {
  private def bits(x: Float) = FloatText.bits(x)
  private def ray(o: (Float, Float, Float), d: (Float, Float, Float)) =
    RayRecord(
      0,
      Seq(o._1, o._2, o._3).map(bits),
      Seq(d._1, d._2, d._3).map(bits),
      bits(0f),
      bits(Float.PositiveInfinity),
      shadow = false
    )

  "NumericRange" should "size a Cornell-box-like scene to 7 exponent bits and refuse e6" in {
    // Camera 800 from the origin, box 560 wide, unit directions: T <= 24 (1600)^3 / (1/sqrt 3) ~ 2^37.3.
    val r = NumericRange(
      559.2,
      105.0,
      Seq(ray((278f, 273f, -800f), (0f, 0f, 1f)), ray((278f, 273f, -800f), (0.577f, 0.577f, 0.578f)))
    )
    assert(r.maxAbs == 800.0)
    assert(r.neededEmax == 39, r)
    assert(r.expBits == 7)
    assert(r.misfit(FloatFormat(7, 23)).isEmpty)
    val why = r.misfit(FloatFormat(6, 9))
    assert(why.exists(w => w.contains("e6m9") && w.contains("-30..31")), why)
  }

  it should "need 8 bits for a mesh offset by 1e6 and refuse coordinates of 1e13 even in FP32" in {
    assert(NumericRange(1e6, 1.0, 1.0, 1.0).expBits == 8)
    val huge = NumericRange(1e13, 1.0, 1.0, 1.0)
    assert(huge.expBits == 9)
    assert(huge.misfit(FloatFormat.FP32).exists(_.contains("overflow")))
  }

  it should "keep the square of the shortest edge normal" in {
    // (1e-6)^2 = 2^-39.9: emin must be <= -40, which e6 (emin -30) misses and e7 (-62) meets.
    val tiny = NumericRange(1.0, 1e-6, 1.0, 1.0)
    assert(tiny.neededEmin == -40)
    assert(tiny.expBits == 7)
  }

  it should "ask for enough mantissa bits to keep the shortest edge two ulps long at the largest coordinate" in {
    // A radius-1 level-3 icosphere (edges ~0.1) at 1e4: 1e4 / 0.1 = 2^16.6, so 18 bits; e8m15 rounds most of it flat.
    assert(NumericRange(1e4, 0.1, 1.0, 1.0).neededManBits == 18)
    assert(NumericRange(800, 105, 1.0, 1.0).neededManBits == 4)
  }

  it should "count a slow ray's direction: a small largest component scales the sheared z" in {
    val slow = NumericRange(1.0, 1.0, Seq(ray((0f, 0f, 0f), (1e-6f, 0f, 0f))))
    assert(slow.dirMin == 1e-6f.toDouble)
    assert(slow.neededEmax > NumericRange(1.0, 1.0, 1.0, 1.0).neededEmax + 19)
  }

  "ScenePackage.sized" should "fit the exponent to the range, keep the mantissa, keep FP32 whole, and never widen past 8 bits" in {
    // The shipped Cornell box, compiled here (nori-bridge must be built: make setup).
    val dir = java.nio.file.Paths.get("build/test-scenes/numeric-range-cornell")
    rtaccel.regress.Bridge.compile(
      java.nio.file.Paths.get("nori-bridge/target/release/nori-bridge"),
      java.nio.file.Paths.get("scenes/cornell-box/cornell-box.xml"),
      dir,
      "primary",
      Seq("--width", "8", "--height", "8")
    )
    val p = ScenePackage.load(dir)
    val needs = p.needs
    assert(needs.extentAbs == 559.2 && needs.smallestEdge > 100, needs) // scene.json prints the f32 extent shortest
    val s = p.sized(AccelConfig.zc706.withFloat(FloatFormat(8, 12)))
    assert(s.triFloat == FloatFormat(7, 12))
    assert(s.stackDepth == 7 && s.maxLeafSize == 2)
    // FP32 keeps its 8 exponent bits: its records then need no converters.
    assert(p.sized(AccelConfig.zc706).triFloat == FloatFormat.FP32)
    // A too-narrow exponent is widened to what the range needs.
    assert(p.sized(AccelConfig.zc706.withFloat(FloatFormat(6, 9))).triFloat == FloatFormat(7, 9))
    val far = p.copy(needs = needs.copy(extentAbs = 1e13))
    assert(far.sized(AccelConfig.zc706).triFloat.expBits == 8)
    assert(far.misfits(far.sized(AccelConfig.zc706)).exists(_.contains("exponent bits")))
  }
}
