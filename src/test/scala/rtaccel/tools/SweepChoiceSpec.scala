package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, TriangleTest}
import rtaccel.fp.FloatFormat

import java.nio.file.Files

/** FLOAT=auto reads the sweep's choice per variant, and says what is missing when it cannot. */
class SweepChoiceSpec extends AnyFlatSpec {
  private def json(text: String) = { val f = Files.createTempFile("sweep", ".json"); Files.writeString(f, text); f }
  private val sweep = json(
    """{"smallest_safe": {"conservative/watertight": "e8m12-cons-wt", "rne/moller": null},
      | "points": [{"name": "e8m12-cons-wt", "config": {"float": "e8m12"}}, {"name": "e8m23-rne-mt", "config": {"float": "e8m23"}}]}""".stripMargin)

  "SweepChoice" should "return the format of the variant's smallest safe point" in {
    assert(SweepChoice.smallestSafe(sweep, TriangleTest.Watertight, BoxRounding.Conservative) == FloatFormat(8, 12))
  }

  it should "refuse a variant with no safe format, a variant not swept, and a missing file, naming the file" in {
    val none = intercept[IllegalArgumentException](SweepChoice.smallestSafe(sweep, TriangleTest.Moller, BoxRounding.Nearest))
    assert(none.getMessage.contains("no format of the sweep is safe for rne/moller"))
    val absent = intercept[IllegalArgumentException](SweepChoice.smallestSafe(sweep, TriangleTest.Watertight, BoxRounding.Nearest))
    assert(absent.getMessage.contains(sweep.toString) && absent.getMessage.contains("rne/watertight"))
    val missing = intercept[IllegalArgumentException](SweepChoice.smallestSafe(sweep.resolveSibling("nope.json"), TriangleTest.Moller, BoxRounding.Nearest))
    assert(missing.getMessage.contains("make speed-vs-error"))
  }
}
