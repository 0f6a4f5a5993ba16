package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** HeadQueue (StorePort's request queue) alone: under random valid and ready every entry leaves once, in order;
  * with both sides always willing it passes one entry a cycle; `enq.ready` only falls while two entries wait; `count` is the entries held.
  */
class HeadQueueSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "HeadQueue"

  it should "pass every entry once, in order, one a cycle when both sides are willing" in Seeded("HeadQueue") { rnd =>
    test(new HeadQueue(UInt(16.W))).withAnnotations(Backends.treadle) { dut =>
      val sent = mutable.Queue.empty[Int]
      var next = 0
      var got = 0
      var held = 0
      for (cycle <- 0 until 2000) {
        // The last 200 cycles: both sides always willing, one entry a cycle.
        val steady = cycle >= 1800
        val offer = steady || rnd.nextInt(3) > 0
        val take = steady || rnd.nextInt(3) > 0
        dut.io.enq.valid.poke(offer.B); dut.io.enq.bits.poke(next.U)
        dut.io.deq.ready.poke(take.B)
        val ready = dut.io.enq.ready.peek().litToBoolean
        dut.io.count.expect(held.U, s"cycle $cycle: count")
        assert(ready || held == 2, s"cycle $cycle: enq.ready low with $held entries")
        if (take && dut.io.deq.valid.peek().litToBoolean) {
          dut.io.deq.bits.expect(sent.dequeue().U, s"cycle $cycle: order")
          held -= 1; if (steady && cycle > 1802) got += 1
        }
        if (offer && ready) { sent.enqueue(next); next = (next + 1) & 0xffff; held += 1 }
        dut.clock.step()
      }
      assert(got == 197, s"$got entries left in 197 steady cycles")
    }
  }
}
