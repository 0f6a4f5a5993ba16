package rtaccel.datapath

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FloatFormat
import rtaccel.{AccelConfig, RtAccel}

/** The datapath plugs into the accelerator: RtAccel elaborates with it (FP32
  * and a narrow format), and names round-trip through `FloatDatapath.parse`.
  */
class RtAccelPlugSpec extends AnyFlatSpec {
  for (
    dp <- Seq(
      FloatDatapath(FloatFormat.FP32, TriangleTest.Moller, BoxRounding.Nearest),
      FloatDatapath(FloatFormat(8, 10), TriangleTest.Watertight, BoxRounding.Conservative)
    )
  ) {
    s"RtAccel with ${dp.name}" should "elaborate" in {
      val cfg = AccelConfig(numRayIds = 4, stackDepth = 4, boxFloat = dp.boxFmt, triFloat = dp.triFmt)
      val chirrtl = _root_.circt.stage.ChiselStage.emitCHIRRTL(new RtAccel(cfg, dp))
      assert(chirrtl.contains(s"PrimIntersect_${dp.name}") && chirrtl.contains(s"BoxLane_${dp.name}"))
      assert(FloatDatapath.parse(dp.name) == dp)
    }
  }

  "FloatDatapath.parse" should "reject a malformed name, naming it" in {
    val e = intercept[IllegalArgumentException](FloatDatapath.parse("e8m23_xx_rne"))
    assert(e.getMessage.contains("xx"))
  }
}
