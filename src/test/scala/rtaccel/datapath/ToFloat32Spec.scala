package rtaccel.datapath

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.fp.FloatFormat
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

/** `toFloat32` of a narrow datapath (combinational widening) against the golden widening. */
class ToFloat32Harness(val dp: FloatDatapath) extends Module {
  val io = IO(new Bundle {
    val in = Input(UInt(dp.fmt.width.W))
    val out = Output(UInt(32.W))
  })
  io.out := dp.toFloat32(AccelConfig(boxFloat = dp.boxFmt, triFloat = dp.triFmt), io.in)
}

class ToFloat32Spec extends AnyFlatSpec with ChiselScalatestTester {
  for (fmt <- Seq(FloatFormat(6, 9), FloatFormat(8, 10))) {
    val dp = FloatDatapath(fmt, TriangleTest.Watertight, BoxRounding.Nearest)
    s"toFloat32 of ${dp.name}" should "widen exactly as the golden model does (special values and a seeded sample)" in
      Seeded(s"ToFloat32Spec ${fmt.name}") { rng =>
        val g = FloatGolden(dp)
        val values: Seq[BigInt] =
          Seq(
            fmt.canonicalNaN,
            fmt.infinity(true),
            fmt.minSubnormal(false),
            fmt.maxSubnormal(true),
            fmt.zero(true),
            fmt.maxFinite(true),
            fmt.minNormal(false)
          ) ++ Seq.fill(10000)(BigInt(fmt.width, rng))
        test(new ToFloat32Harness(dp)).withAnnotations(Backends.treadle) { dut =>
          for (x <- values) {
            dut.io.in.poke(x.U)
            val want = g.toFloat32(x)
            val got = dut.io.out.peek().litValue
            // The golden FpModel gives the canonical NaN too.
            assert(got == BigInt(want), f"${fmt.name} 0x${x.toLong}%x: hw 0x${got.toLong}%08x golden 0x$want%08x")
          }
        }
      }
  }
}
