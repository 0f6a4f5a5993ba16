package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, TriangleTest}
import rtaccel.fp.FloatFormat

import java.nio.file.Files

/** FLOAT=auto reads the sweep's choice per variant, and says what is missing when it cannot. */
class SweepChoiceSpec extends AnyFlatSpec {
  private def json(text: String) = { val f = Files.createTempFile("sweep", ".json"); Files.writeString(f, text); f }
  private val sweep = json(
    """{"smallest_safe": {"conservative/watertight": "e8m12-cons-wt", "rne/moller": null, "conservative/moller": "4q-e8m10-e8m23-cons-mt"},
      | "points": [{"name": "e8m12-cons-wt", "config": {"float": "e8m12"}}, {"name": "e8m23-rne-mt", "config": {"float": "e8m23"}},
      |   {"name": "4q-e8m10-e8m23-cons-mt", "config": {"float": "e8m10e8m23", "layout": "4q", "box_float": "e8m10", "tri_float": "e8m23"}}]}""".stripMargin
  )

  "SweepChoice" should "return the formats of the variant's smallest safe point (one format for both in older sweeps)" in {
    assert(SweepChoice.smallestSafe(sweep, TriangleTest.Watertight, BoxRounding.Conservative) == ((
      FloatFormat(8, 12),
      FloatFormat(8, 12)
    )))
    assert(SweepChoice.smallestSafePoint(sweep, TriangleTest.Watertight, BoxRounding.Conservative)._3 == "nori")
    assert(SweepChoice.smallestSafePoint(sweep, TriangleTest.Moller, BoxRounding.Conservative) ==
      ((FloatFormat(8, 10), FloatFormat.FP32, "4q")))
  }

  it should "refuse a variant with no safe format, a variant not swept, and a missing file, naming the file" in {
    val none =
      intercept[IllegalArgumentException](SweepChoice.smallestSafe(sweep, TriangleTest.Moller, BoxRounding.Nearest))
    assert(none.getMessage.contains("no format of the sweep is safe for rne/moller"))
    val absent =
      intercept[IllegalArgumentException](SweepChoice.smallestSafe(sweep, TriangleTest.Watertight, BoxRounding.Nearest))
    assert(absent.getMessage.contains(sweep.toString) && absent.getMessage.contains("rne/watertight"))
    val missing = intercept[IllegalArgumentException](SweepChoice.smallestSafe(
      sweep.resolveSibling("nope.json"),
      TriangleTest.Moller,
      BoxRounding.Nearest
    ))
    assert(missing.getMessage.contains("make speed-vs-error"))
  }
}
