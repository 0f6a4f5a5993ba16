package rtaccel.sweep

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.BoxTest

/** A sweep point's command line: the box test is part of the point. */
class SweepArgsSpec extends AnyFlatSpec {
  private def args(extra: String*) = SweepArgs.parse(
    Seq(
      "--float",
      "e8m23",
      "--rounding",
      "conservative",
      "--triangle",
      "watertight",
      "--sweep",
      "build/sweep",
      "--runs",
      "cornell-box-primary"
    ) ++ extra
  )

  "SweepArgs.parse" should "name a grid point with -grid after the point's fields and configure its grid box test" in {
    val a = args("--bvh", "4q", "--box-test", "grid")
    assert(a.boxTest == BoxTest.Grid)
    assert(a.name == "4q-e8m23-e8m23-cons-wt-grid")
    assert(a.config.gridBox && a.config.layout.name == "4q")
    val plain = args("--bvh", "4q")
    assert(plain.boxTest == BoxTest.Fp32 && plain.name == "4q-e8m23-e8m23-cons-wt" && !plain.config.gridBox)
  }

  it should "refuse a grid box test on plain nodes or with narrow box constants, naming the option" in {
    val plain = intercept[IllegalArgumentException](args("--bvh", "4", "--box-test", "grid"))
    assert(plain.getMessage.contains("--box-test") && plain.getMessage.contains("quantized"), plain.getMessage)
    val narrow =
      intercept[IllegalArgumentException](args("--bvh", "4q", "--box-test", "grid", "--box-float", "e8m10"))
    assert(narrow.getMessage.contains("--box-test") && narrow.getMessage.contains("FP32"), narrow.getMessage)
    val odd = intercept[IllegalArgumentException](args("--bvh", "4q", "--box-test", "slab"))
    assert(odd.getMessage.contains("box test 'slab'"), odd.getMessage)
  }
}
