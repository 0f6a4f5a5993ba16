package rtaccel.fp

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded

/** The reciprocal's Newton-Raphson plan ([[FpRecipPlan]]), in the integers the
  * hardware computes, against the exact quotient `floor(2^(2p) / B)` and
  * remainder: every normalised significand of every precision from 3 to 24
  * (FP32's), and random and edge significands up to 53 bits. Pure Scala.
  */
class FpRecipPlanSpec extends AnyFlatSpec {
  behavior of "FpRecipPlan"

  private def check(plan: FpRecipPlan, b: BigInt): Unit = {
    val p = plan.p
    val (q, exact) = plan.soft(b)
    val num = BigInt(1) << (2 * p)
    assert(
      q == num / b && exact == (num % b == 0),
      s"p=$p B=$b: plan gives ($q, $exact), exact (${num / b}, ${num % b == 0}); plan $plan"
    )
  }

  it should "give the exact quotient and remainder test for every significand of precision 3 to 24" in {
    for (p <- 3 to 24) {
      val plan = FpRecipPlan(p)
      var b = BigInt(1) << (p - 1)
      val end = BigInt(1) << p
      while (b < end) { check(plan, b); b += 1 }
      println(s"FpRecipPlan($p): ${plan.steps.size} Newton steps, all ${BigInt(1) << (p - 1)} significands exact")
    }
  }

  it should "give the exact quotient for random and edge significands of precision 25 to 53" in
    Seeded("FpRecipPlanSpec.wide") { rnd =>
      for (p <- 25 to 53) {
        val plan = FpRecipPlan(p)
        val lo = BigInt(1) << (p - 1)
        val edges = Seq(lo, lo + 1, lo + 2, 2 * lo - 1, 2 * lo - 2) ++
          (0 until plan.indexBits + 1).flatMap(j => Seq(lo + (lo >> j), lo + (lo >> j) - 1, lo + (lo >> j) + 1))
        val random = Seq.fill(20000)(lo + BigInt(p - 1, rnd.self))
        (edges ++ random).filter(b => b >= lo && b < 2 * lo).foreach(check(plan, _))
      }
    }

  it should "use at most two Newton steps up to FP32's precision" in {
    assert(FpRecipPlan(24).steps.size == 2 && FpRecipPlan(9).steps.isEmpty)
  }
}
