package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** HeldCount in a module of its own: two entry and two exit handshakes, the count out. */
class HeldCountTop(width: Int) extends Module {
  val io = IO(new Bundle {
    val enters = Input(Vec(2, Bool()))
    val leaves = Input(Vec(2, Bool()))
    val count = Output(UInt(width.W))
  })
  io.count := HeldCount(io.enters, io.leaves, width)
}

/** HeldCount reads, every cycle, the items that entered before that cycle less those that left before it,
  * modulo 2^width: the value a register updated by every handshake would hold. Random handshakes that keep the
  * true count between 0 and the width's range, crossing it both ways many times. */
class HeldCountSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "HeldCount"

  it should "equal the count of entries less exits before each cycle" in Seeded("HeldCount.w4") { rnd =>
    val width = 4
    test(new HeldCountTop(width)).withAnnotations(Backends.treadle) { dut =>
      var held = 0
      var peak = 0
      for (cycle <- 0 until 4000) {
        dut.io.count.expect(held.U, s"cycle $cycle: $held items held")
        // Drift up for a while, then down, so the count sweeps its whole range.
        val rising = (cycle / 200) % 2 == 0
        val enters = Seq.fill(2)(rnd.nextInt(4) < (if (rising) 2 else 1) && held < (1 << width) - 3)
        val leaves = Seq.fill(2)(rnd.nextInt(4) < (if (rising) 1 else 2) && held > 2)
        enters.zip(dut.io.enters).foreach { case (e, p) => p.poke(e.B) }
        leaves.zip(dut.io.leaves).foreach { case (l, p) => p.poke(l.B) }
        dut.clock.step()
        held += enters.count(identity) - leaves.count(identity)
        peak = peak.max(held)
      }
      assert(peak >= (1 << width) - 3, s"the count reached only $peak: the test missed the top of its range")
    }
  }
}
