package rtaccel

import chisel3._
import chiseltest._
import firrtl2.AnnotationSeq
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

import scala.collection.mutable

class RayIdFreeListSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RayIdFreeList"

  it should "hand out every ID exactly once straight after reset" in {
    test(new RayIdFreeList(8)).withAnnotations(Backends.treadle) { dut =>
      dut.io.free.valid.poke(false.B)
      dut.io.alloc.ready.poke(true.B)
      val seen = (0 until 8).map { _ =>
        dut.io.alloc.valid.expect(true.B)
        val id = dut.io.alloc.bits.peek().litValue.toInt
        dut.clock.step()
        id
      }
      assert(seen.sorted == (0 until 8), s"IDs issued: $seen")
      dut.io.alloc.valid.expect(false.B, "pool must be empty after 8 allocations")
      dut.io.inFlight.expect(8.U)
    }
  }

  it should "flag and drop a free of an ID that is not allocated" in {
    test(new RayIdFreeList(4)).withAnnotations(Backends.treadle) { dut =>
      dut.io.alloc.ready.poke(false.B)
      dut.io.free.valid.poke(true.B)
      dut.io.free.bits.poke(2.U) // never allocated
      dut.clock.step()
      dut.io.free.valid.poke(false.B)
      dut.io.doubleFree.expect(true.B)
      dut.io.inFlight.expect(0.U)
      // The pool still holds each ID once: 4 allocations, then empty.
      dut.io.alloc.ready.poke(true.B)
      val ids = (0 until 4).map { _ =>
        val id = dut.io.alloc.bits.peek().litValue; dut.clock.step(); id
      }
      assert(ids.distinct.size == 4, s"IDs issued: $ids")
      dut.io.alloc.valid.expect(false.B)
    }
  }

  /** Random alloc/free traffic with random ready/valid, checked by a scoreboard. */
  private def randomTraffic(numIds: Int, cycles: Int, annos: AnnotationSeq, name: String): Unit =
    Seeded(name) { rnd =>
      test(new RayIdFreeList(numIds)).withAnnotations(annos) { dut =>
        val held = mutable.ArrayBuffer.empty[Int]
        var allocs = 0
        var justFreed = 0
        for (cycle <- 0 until cycles) {
          val wantAlloc = rnd.nextInt(4) != 0
          val doFree = held.nonEmpty && rnd.nextInt(3) == 0
          val freeIdx = if (doFree) rnd.nextInt(held.size) else 0
          dut.io.alloc.ready.poke(wantAlloc.B)
          dut.io.free.valid.poke(doFree.B)
          if (doFree) dut.io.free.bits.poke(held(freeIdx).U)
          // The pool is empty exactly when every ID is held or was freed in the cycle before: a freed ID is
          // handed out again from the second cycle after its free (it enters the FIFO a cycle late).
          val valid = dut.io.alloc.valid.peek().litToBoolean
          assert(
            valid == (held.size + justFreed < numIds),
            s"cycle $cycle: alloc.valid=$valid with ${held.size}/$numIds held, $justFreed freed last cycle"
          )
          dut.io.inFlight.expect(held.size.U, s"cycle $cycle")
          val got = if (valid && wantAlloc) Some(dut.io.alloc.bits.peek().litValue.toInt) else None
          dut.clock.step()
          if (doFree) held.remove(freeIdx)
          justFreed = if (doFree) 1 else 0
          got.foreach { id =>
            assert(!held.contains(id), s"cycle $cycle: ID $id handed out while still held")
            assert(id >= 0 && id < numIds, s"cycle $cycle: ID $id out of range")
            held += id
            allocs += 1
          }
        }
        dut.io.doubleFree.expect(false.B)
        assert(allocs > cycles / 4, s"only $allocs allocations in $cycles cycles: throughput collapsed")
      }
    }

  it should "never duplicate or lose an ID under random traffic (treadle)" in {
    randomTraffic(numIds = 4, cycles = 2000, Backends.treadle, "RayIdFreeList.random.treadle")
  }

  it should "never duplicate or lose an ID under random traffic (Verilator)" in {
    randomTraffic(numIds = 16, cycles = 20000, Backends.verilator, "RayIdFreeList.random.verilator")
  }
}
