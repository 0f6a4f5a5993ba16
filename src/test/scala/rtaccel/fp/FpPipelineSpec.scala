package rtaccel.fp

import org.scalatest.flatspec.AnyFlatSpec

/** The register plan behind every unit's latency parameter (the units' exact
  * latencies are checked cycle by cycle in FpUnitsSpec).
  */
class FpPipelineSpec extends AnyFlatSpec {
  "FpPipeline" should "place exactly `latency` registers, spread evenly over the cut points" in {
    for (latency <- 0 to 40; cuts <- 1 to 30) {
      val plan = new FpPipeline(latency, cuts)
      val regs = (0 until cuts).map(plan.registersAt)
      assert(regs.sum == latency, s"L=$latency K=$cuts: $regs")
      assert(regs.max - regs.min <= 1, s"L=$latency K=$cuts: uneven $regs")
    }
  }

  it should "put the single register of a latency-1 unit at its output" in {
    assert(new FpPipeline(1, 2).registersAt(1) == 1 && new FpPipeline(1, 28).registersAt(27) == 1)
  }

  it should "reject a negative latency" in {
    intercept[IllegalArgumentException](new FpPipeline(-1, 2))
  }
}
