package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** PerfCounter in a module of its own, the counter and nothing else. */
class PerfCounterTop(width: Int, incBits: Int) extends Module {
  val io = IO(new Bundle {
    val inc = Input(UInt(incBits.W))
    val count = Output(UInt(width.W))
  })
  io.count := PerfCounter(io.inc, width)
}

/** PerfCounter in narrow widths, so that the low half wraps many times: every cycle its count equals the
  * sum of the increments so far, modulo 2^width, for random increments of every size its input allows. */
class PerfCounterSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PerfCounter"

  for ((width, incBits) <- Seq((3, 1), (8, 1), (12, 3), (16, 6))) {
    it should s"count exactly across its three parts ($width bits, increments below 2^$incBits)" in
      Seeded(s"PerfCounter.w$width.i$incBits") { rnd =>
        test(new PerfCounterTop(width, incBits)).withAnnotations(Backends.treadle) { dut =>
          val mod = BigInt(1) << width
          var sum = BigInt(0)
          var wraps = 0
          for (cycle <- 0 until 8 * (1 << width) / ((1 << incBits) - 1)) {
            dut.io.count.expect(sum.U, s"cycle $cycle: count after increments summing to $sum")
            // Mostly the largest increments, so the count sweeps the whole range and wraps.
            val inc = if (rnd.nextInt(4) == 0) rnd.nextInt(1 << incBits) else (1 << incBits) - 1 - rnd.nextInt(2)
            dut.io.inc.poke(inc.U)
            dut.clock.step()
            if (sum + inc >= mod) wraps += 1
            sum = (sum + inc) % mod
          }
          assert(wraps >= 2, s"the count wrapped only $wraps times: the test missed the carries into the wider parts")
        }
      }
  }
}
