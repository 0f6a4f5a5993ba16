package rtaccel

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** One arbiter's outputs, and which inputs it took. */
class ArbiterView(n: Int) extends Bundle {
  val valid = Bool()
  val bits = UInt(8.W)
  val chosen = UInt(log2Ceil(n).max(1).W)
  val fire = Vec(n, Bool())
}

/** RoundRobinArbiter beside chisel3.util's RRArbiter, both fed the same valids, bits and out.ready. */
class RoundRobinPair(n: Int) extends Module {
  val io = IO(new Bundle {
    val valid = Input(Vec(n, Bool()))
    val bits = Input(Vec(n, UInt(8.W)))
    val outReady = Input(Bool())
    val ours = Output(new ArbiterView(n))
    val theirs = Output(new ArbiterView(n))
  })
  for (
    (a, o) <- Seq(
      Module(new RoundRobinArbiter(UInt(8.W), n)).io -> io.ours,
      Module(new RRArbiter(UInt(8.W), n)).io -> io.theirs
    )
  ) {
    for (i <- 0 until n) {
      a.in(i).valid := io.valid(i); a.in(i).bits := io.bits(i)
      o.fire(i) := a.in(i).fire
    }
    a.out.ready := io.outReady
    o.valid := a.out.valid; o.bits := a.out.bits; o.chosen := a.chosen
  }
}

/** Every cycle of random valids and back-pressure, RoundRobinArbiter grants what RRArbiter grants: the same
  * out.valid and, when valid, the same chosen input, bits and input handshake (so the same pointer next cycle). */
class RoundRobinArbiterSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RoundRobinArbiter"

  for (n <- Seq(1, 2, 3, 8))
    it should s"grant as RRArbiter does, cycle for cycle ($n inputs)" in Seeded(s"RoundRobinArbiter.n$n") { rnd =>
      test(new RoundRobinPair(n)).withAnnotations(Backends.treadle) { dut =>
        var grants = 0
        for (cycle <- 0 until 3000) {
          val busy = rnd.nextInt(4) // 0: sparse valids .. 3: all valid
          for (i <- 0 until n) {
            dut.io.valid(i).poke((busy == 3 || rnd.nextInt(4) < busy).B)
            dut.io.bits(i).poke(rnd.nextInt(256).U)
          }
          dut.io.outReady.poke((rnd.nextInt(5) > 0).B)
          val v = dut.io.theirs.valid.peek().litToBoolean
          assert(dut.io.ours.valid.peek().litToBoolean == v, s"cycle $cycle: out.valid differs")
          if (v) {
            val c = dut.io.theirs.chosen.peek().litValue
            assert(dut.io.ours.chosen.peek().litValue == c, s"cycle $cycle: chosen differs (RRArbiter $c)")
            assert(dut.io.ours.bits.peek().litValue == dut.io.theirs.bits.peek().litValue, s"cycle $cycle: bits differ")
          }
          for (i <- 0 until n)
            assert(
              dut.io.ours.fire(i).peek().litToBoolean == dut.io.theirs.fire(i).peek().litToBoolean,
              s"cycle $cycle: input $i's handshake differs"
            )
          if (v && dut.io.outReady.peek().litToBoolean) grants += 1
          dut.clock.step()
        }
        assert(grants > 1000, s"only $grants grants: the test drove too little")
      }
    }
}
