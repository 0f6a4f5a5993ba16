package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath._
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

class GridNodeStageSpec extends AnyFlatSpec with ChiselScalatestTester {
  import GridBoxCheck._

  "GridNodeStage" should "give every field of GridNode.soft bit for bit, under random valid gaps" in {
    val p = GridParams()
    val rays = new RayConsts(f32, f32, TriangleTest.Moller, BoxRounding.Conservative)
    test(new GridNodeStage(p, rays)).withAnnotations(Backends.verilator) { dut =>
      Seeded("GridNodeStageSpec.hardware") { r =>
        val expect = scala.collection.mutable.Queue.empty[(GridCase, GridNodeFixed)]
        val total = 3000
        var (sent, checked) = (0, 0)
        while (checked < total) {
          val send = sent < total && r.nextInt(4) != 0
          dut.io.in.valid.poke(send.B)
          if (send) {
            val c = randomCase(r, p, 1)
            pokeNode(dut.io.in.bits, c, c.s.map(_ + 127))
            expect.enqueue((c, golden(f32, p, c)._1))
            sent += 1
          }
          dut.clock.step()
          if (dut.io.out.valid.peek().litToBoolean) {
            val (c, want) = expect.dequeue()
            val o = dut.io.out.bits
            def b(x: Bool) = x.peek().litToBoolean
            def v(x: Bits) = x.peek().litValue
            val got = GridNodeFixed(
              o.axes.map(a =>
                GridAxisFixed(
                  b(a.flat),
                  b(a.neg),
                  v(a.stepLo),
                  v(a.stepHi),
                  b(a.stepHiSat),
                  v(a.cLo),
                  b(a.cLoBelow),
                  v(a.cHi),
                  b(a.cHiAbove),
                  v(a.gHi),
                  v(a.gLo)
                )
              ),
              v(o.tmin),
              v(o.tmax),
              b(o.err)
            )
            assert(!b(dut.io.badScale), s"badScale on $c")
            assert(got == want, s"RTL $got, golden $want: $c")
            checked += 1
          }
        }
        assert(expect.isEmpty && checked == total)
      }
    }
  }
}
