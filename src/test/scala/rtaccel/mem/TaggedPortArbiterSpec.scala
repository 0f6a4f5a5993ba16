package rtaccel.mem

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

import scala.collection.mutable

class TaggedPortArbiterSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "TaggedPortArbiter"

  private val p = MemPortParams(addrBits = 16, tagBits = 3, recordBytes = 4)

  it should "grant contending clients in turn and route responses back by tag" in Seeded("TaggedPortArbiter.rr") {
    rnd =>
      test(new TaggedPortArbiter(p, 3)).withAnnotations(Backends.treadle) { dut =>
        val grants = mutable.ArrayBuffer.empty[Int]
        dut.io.mem.req.ready.poke(true.B)
        dut.io.mem.resp.valid.poke(false.B)
        for (c <- 0 until 3) dut.io.clients(c).resp.ready.poke(true.B)
        for (cycle <- 0 until 30) {
          for (c <- 0 until 3) {
            dut.io.clients(c).req.valid.poke(true.B)
            dut.io.clients(c).req.bits.addr.poke((100 * c + cycle).U)
            dut.io.clients(c).req.bits.tag.poke((cycle % 8).U)
          }
          val tag = dut.io.mem.req.bits.tag.peek().litValue.toInt
          val src = tag >> 3
          assert((tag & 7) == cycle % 8, s"cycle $cycle: client tag not preserved")
          dut.io.mem.req.bits.addr.expect((100 * src + cycle).U, s"cycle $cycle: address of client $src")
          dut.io.clients(src).req.ready.expect(true.B)
          grants += src
          dut.clock.step()
        }
        // Under full contention each client gets exactly every third grant.
        assert(grants.grouped(3).forall(_.sorted == Seq(0, 1, 2)), s"grants not round-robin: $grants")

        for (c <- 0 until 3) dut.io.clients(c).req.valid.poke(false.B)
        for (i <- 0 until 200) {
          val src = rnd.nextInt(3); val tag = rnd.nextInt(8); val data = rnd.nextInt(1 << 30)
          val ready = Seq.fill(3)(rnd.nextBoolean())
          for (c <- 0 until 3) dut.io.clients(c).resp.ready.poke(ready(c).B)
          dut.io.mem.resp.valid.poke(true.B)
          dut.io.mem.resp.bits.tag.poke(((src << 3) | tag).U)
          dut.io.mem.resp.bits.data.poke(data.U)
          for (c <- 0 until 3) dut.io.clients(c).resp.valid.expect((c == src).B, s"response $i for client $src")
          dut.io.clients(src).resp.bits.tag.expect(tag.U)
          dut.io.clients(src).resp.bits.data.expect(data.U)
          dut.io.mem.resp.ready.expect(ready(src).B, s"response $i: shared ready must be client $src's")
          dut.clock.step()
        }
      }
  }
}
