package rtaccel.fp

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** Directed FP32 operand pairs for the adder's alignment (on DSP48E1s, a product split over two DSPs at
  * FP32, which the exhaustive e4m3 run does not reach) and normaliser, and the multiplier's rounding:
  * every alignment distance 0..40 with the smaller operand's ones placed around the sticky boundary and the
  * DSP chunk boundary, cancellation to zero and to a few ulps (massive cancellation) at every exponent near
  * the subnormal boundary, subnormal results, overflow to infinity or the largest finite, and rounding that
  * carries into the next binade; each pair in both orders and sign combinations, in every mode, through
  * every port of [[FpUnitsHarness]] against the golden model.
  */
class FpDirectedSpec extends AnyFlatSpec with ChiselScalatestTester {
  private val F = FloatFormat.FP32
  private val m = F.manBits
  private val fracMask = (BigInt(1) << m) - 1

  private def pairs(rnd: scala.util.Random): Seq[(BigInt, BigInt)] = {
    def f(e: Int, frac: BigInt) = F.pack(false, e, frac & fracMask)
    val fracs = Seq(BigInt(0), fracMask, BigInt(1), BigInt(1) << (m - 1), fracMask - 1, BigInt(m, rnd))
    // Alignment: every distance, the smaller operand's ones at each place around where they fall off.
    val align = for {
      ea <- Seq(1, 2, 30, 127, 200, 254)
      d <- 0 to 40 if ea - d >= 0
      fa <- Seq(BigInt(0), fracMask, BigInt(m, rnd))
      fb <- fracs ++ (0 until m by 3).map(k => BigInt(1) << k) ++ Seq((BigInt(1) << (d.min(m))) - 1)
    } yield (f(ea, fa), f(ea - d, fb))
    // Cancellation: a - (a +- k ulps), to zero and to a few ulps, at exponents near the subnormal boundary.
    val cancel = for {
      e <- Seq(0, 1, 2, 3, 24, 25, 26, 27, 28, 100, 254)
      fa <- fracs
      k <- -3 to 3
      a = f(e, fa)
      b = a + k if b >= 0 && b < F.infinity(false)
    } yield (a, b ^ (BigInt(1) << (F.width - 1)))
    // Overflow and carries into the next binade.
    val big = Seq(F.maxFinite(false), F.maxFinite(false) - 1, f(254, 0), f(253, fracMask))
    val over = for (a <- big; b <- big ++ Seq(f(230, 0), f(231, fracMask), f(229, 0), f(100, 0))) yield (a, b)
    val carry = for (e <- Seq(1, 2, 50, 127, 253); d <- 1 to 27; fb <- fracs)
      yield (f(e, fracMask), f(e - d.min(e), fb))
    // Subnormal results and operands.
    val sub = for (_ <- 0 until 2000) yield (f(rnd.nextInt(3), BigInt(m, rnd)), f(rnd.nextInt(3), BigInt(m, rnd)))
    val all = align ++ cancel ++ over ++ carry ++ sub
    val signBit = BigInt(1) << (F.width - 1)
    all.flatMap { case (a, b) => Seq((a, b), (b, a), (a ^ signBit, b), (a, b ^ signBit)) }
  }

  "The FP32 units" should "match the golden model on directed alignment, cancellation, subnormal, overflow and carry cases in every mode" in
    Seeded("FpDirected.e8m23") { rnd =>
      val ps = pairs(rnd)
      val vectors = (for (rm <- RoundingMode.all; (a, b) <- ps)
        yield FpVector(a, b, FpOperands.single(F, rnd), rm, valid = true)).toIndexedSeq
      test(new FpUnitsHarness(F, None, FpHarnessLatencies.defaults(F))).withAnnotations(Backends.verilator) { dut =>
        val checked = FpUnitsDriver.run(dut, vectors, jvmCheck = true)
        assert(checked.values.forall(_ == vectors.size) && checked.size == 8, s"checked: $checked")
        info(s"${vectors.size} vectors x 8 ports")
      }
    }
}
