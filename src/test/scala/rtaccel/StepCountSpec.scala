package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** StepCount in a module of its own: the two events in, the count and its flags out. */
class StepCountTop(width: Int, val flagValues: Seq[Int], init: Int) extends Module {
  val io = IO(new Bundle {
    val up = Input(Bool())
    val down = Input(Bool())
    val count = Output(UInt(width.W))
    val flags = Output(Vec(flagValues.size, Bool()))
    val agree = Output(Bool())
  })
  private val c = new StepCount("c", width, flagValues, init)
  c.step(io.up, io.down)
  io.count := c.countReg
  io.flags := VecInit(flagValues.map(c.is))
  io.agree := c.flagsAgree
}

/** StepCount holds, every cycle, its initial value plus the cycles with `up` alone less those with `down` alone,
  * and each flag is whether it holds that value. Random events that keep the count inside its width's range,
  * sweeping it from end to end both ways many times; flags at both ends, in the middle, and one beyond the width
  * (a constant false). */
class StepCountSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "StepCount"

  it should "count the steps and keep each flag equal to its compare" in Seeded("StepCount.w4") { rnd =>
    val width = 4
    val top = (1 << width) - 1
    val flagValues = Seq(0, 1, 2, 7, top, top + 1)
    val init = 3
    test(new StepCountTop(width, flagValues, init)).withAnnotations(Backends.treadle) { dut =>
      var count = init
      val seen = Array.fill(top + 1)(false)
      for (cycle <- 0 until 4000) {
        dut.io.count.expect(count.U, s"cycle $cycle")
        for ((k, i) <- flagValues.zipWithIndex)
          dut.io.flags(i).expect((count == k).B, s"cycle $cycle: count $count, flag of $k")
        dut.io.agree.expect(true.B, s"cycle $cycle: flagsAgree")
        seen(count) = true
        // Drift up for a while, then down, so the count sweeps its whole range.
        val rising = (cycle / 100) % 2 == 0
        val up = rnd.nextInt(4) < (if (rising) 3 else 1) && count < top
        val down = rnd.nextInt(4) < (if (rising) 1 else 3) && count > 0
        dut.io.up.poke(up.B)
        dut.io.down.poke(down.B)
        dut.clock.step()
        count += (if (up && !down) 1 else 0) - (if (down && !up) 1 else 0)
      }
      assert(seen.forall(identity), s"the count missed ${seen.indices.filterNot(seen).mkString(", ")}")
    }
  }
}
