package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** RamQueue alone: under random valid and ready every entry leaves once, in order, and `count` is the entries held;
  * `enq.ready` falls only when `entries` wait in the memory; with both sides always willing it passes one entry a
  * cycle; and it holds `RamQueue.capacity(entries)` before refusing one.
  */
class RamQueueSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RamQueue"

  for (entries <- Seq(2, 5, 16)) {
    it should s"pass every entry once, in order, one a cycle when both sides are willing ($entries entries)" in Seeded(
      s"RamQueue$entries"
    ) { rnd =>
      test(new RamQueue(UInt(16.W), entries)).withAnnotations(Backends.treadle) { dut =>
        val sent = mutable.Queue.empty[Int]
        var next = 0
        var got = 0
        var held = 0
        var maxHeld = 0
        for (cycle <- 0 until 3000) {
          // Phases: random; fill (no reads) to find the capacity; random again; both sides always willing.
          val filling = cycle >= 1000 && cycle < 1100
          val steady = cycle >= 2800
          val offer = steady || filling || rnd.nextInt(3) > 0
          val take = steady || (!filling && rnd.nextInt(3) > 0)
          dut.io.enq.valid.poke(offer.B); dut.io.enq.bits.poke(next.U)
          dut.io.deq.ready.poke(take.B)
          dut.io.count.expect(held.U, s"cycle $cycle: count")
          val ready = dut.io.enq.ready.peek().litToBoolean
          assert(ready || held >= entries, s"cycle $cycle: enq.ready low with $held entries held")
          if (take && dut.io.deq.valid.peek().litToBoolean) {
            dut.io.deq.bits.expect(sent.dequeue().U, s"cycle $cycle: order")
            held -= 1; if (steady && cycle > 2810) got += 1
          }
          if (offer && ready) { sent.enqueue(next); next = (next + 1) & 0xffff; held += 1 }
          maxHeld = maxHeld.max(held)
          dut.clock.step()
        }
        assert(maxHeld == RamQueue.capacity(entries), s"held at most $maxHeld, capacity ${RamQueue.capacity(entries)}")
        assert(got == 189, s"$got entries left in 189 steady cycles")
      }
    }
  }
}
