package rtaccel.fp

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

/** Every unit, every format the project uses, every rounding mode, bit-exact
  * against the golden model (and FP32 RNE against JVM `Float`), on Verilator.
  * One build per harness: 9 Verilator builds in all (six formats with a
  * runtime `rm` port, e4m3 exhaustively, FP32 with RNE fixed at elaboration
  * and other latencies, e6m9 with RDN fixed). Treadle is too slow here (~45 vectors/s).
  */
class FpUnitsSpec extends AnyFlatSpec with ChiselScalatestTester {
  import RoundingMode._
  private val F32 = FloatFormat.FP32

  /** Corners in all modes, then `perMode(rm)` random vectors per mode; asserts every port saw them all. */
  private def runHarness(
      fmt: FloatFormat,
      rm: Option[RoundingMode],
      lat: FpHarnessLatencies,
      perMode: RoundingMode => Int,
      name: String,
      minValidRandomRne: Int = 0
  ): Unit = Seeded(name) { rnd =>
    val modes = rm.map(Seq(_)).getOrElse(RoundingMode.all)
    val random = modes.flatMap(m => FpVector.random(fmt, m, perMode(m), rnd))
    val validRne = random.count(v => v.valid && v.rm == RNE)
    assert(validRne >= minValidRandomRne, s"only $validRne valid random RNE vectors, need $minValidRandomRne")
    val vectors = (FpVector.corners(fmt, modes) ++ random).toIndexedSeq
    test(new FpUnitsHarness(fmt, rm, lat)).withAnnotations(Backends.verilator) { dut =>
      val t0 = System.nanoTime()
      val checked = FpUnitsDriver.run(dut, vectors, jvmCheck = fmt == F32)
      val valid = vectors.count(_.valid)
      for (port <- Seq("add", "sub", "mul", "div", "recip", "cmp", "fromF32", "toF32"))
        assert(checked.getOrElse(port, 0) == valid, s"$port checked ${checked.getOrElse(port, 0)} of $valid results")
      info(
        f"$fmt ${RoundingMode.tag(rm)}: ${vectors.size} vectors ($valid valid) x 8 ports in ${(System.nanoTime() - t0) / 1e9}%.1f s"
      )
    }
  }

  "FP units (e8m23, runtime rm)" should "match JVM Float in RNE (corners + 100,000 random) and the model in RTZ/RDN/RUP (20,000 each)" in
    runHarness(
      F32,
      None,
      FpHarnessLatencies.defaults(F32),
      m => if (m == RNE) 110000 else 20000,
      "FpUnits.e8m23.dyn",
      minValidRandomRne = 100000
    )

  for (fmt <- Seq(FloatFormat(8, 15), FloatFormat(8, 12), FloatFormat(8, 10), FloatFormat(8, 7), FloatFormat(6, 9))) {
    s"FP units ($fmt, runtime rm)" should "match the golden model on corners and 20,000 random vectors per mode" in
      runHarness(fmt, None, FpHarnessLatencies.defaults(fmt), _ => 20000, s"FpUnits.$fmt.dyn")
  }

  "FP units (e8m23, fixed RNE, other latencies)" should "match JVM Float with the mode fixed at elaboration" in
    runHarness(
      F32,
      Some(RNE),
      FpHarnessLatencies(add = 0, mul = 3, div = 1, recip = 2, cmp = 0, conv = 2),
      _ => 20000,
      "FpUnits.e8m23.rne"
    )

  "FP units (e4m3, runtime rm)" should "match the golden model on every operand pair in every mode (exhaustive)" in
    Seeded("FpUnits.e4m3.exhaustive") { rnd =>
      val fmt = FloatFormat(4, 3)
      val all = (0 until (1 << fmt.width)).map(BigInt(_))
      val vectors = (for (m <- RoundingMode.all; a <- all; b <- all)
        yield FpVector(a, b, FpOperands.single(F32, rnd), m, valid = true)).toIndexedSeq
      test(new FpUnitsHarness(fmt, None, FpHarnessLatencies.defaults(fmt))).withAnnotations(Backends.verilator) { dut =>
        val checked = FpUnitsDriver.run(dut, vectors, jvmCheck = false)
        assert(checked.values.forall(_ == vectors.size) && checked.size == 8, s"checked: $checked")
      }
    }

  "FP units (e6m9, fixed RDN, latency 1)" should "match the golden model with a directed mode fixed at elaboration" in
    runHarness(FloatFormat(6, 9), Some(RDN), FpHarnessLatencies(1, 1, 1, 1, 1, 1), _ => 20000, "FpUnits.e6m9.rdn")
}
