package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.ErrorFlags
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** HitDma alone: each core offers its share of a batch's hits with seeded
  * random valid (held until taken), the write port takes records with random
  * ready. The scoreboard is the batch, ray by ray: every ray's record is
  * written exactly once, at HIT_BASE + 32 * number, with the documented bytes;
  * the error counters count the batch's flags; a second batch starts clean.
  */
class HitDmaSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "HitDma"

  private final case class Hit(number: Int, hit: Boolean, t: Long, u: Long, v: Long, prim: Int, errors: Int) {

    /** The 32-byte record as docs/register-map.md gives it: number, status, t, u, v, prim, 0, 0. */
    def record: BigInt = {
      val status = BigInt(errors) << HitDma.StatusErrorShift | (if (hit) 1 else 0)
      Seq(BigInt(number), status, BigInt(t), BigInt(u), BigInt(v), BigInt(prim)).zipWithIndex
        .map { case (w, k) => w << (32 * k) }.reduce(_ | _)
    }
  }

  it should "write every hit of a batch once, at its number's address, under random back-pressure (2 cores)" in
    Seeded("HitDma.batches") { rnd =>
      val sys = SystemConfig(cores = 2)
      test(new HitDma(sys)).withAnnotations(Backends.treadle) { dut =>
        for ((base, count) <- Seq((0x10000000L, 157), (0x2000L, 61))) {
          dut.io.hitBase.poke(base.U); dut.io.rayCount.poke(count.U)
          dut.io.start.poke(true.B); dut.clock.step(); dut.io.start.poke(false.B)
          dut.io.errCount.foreach(_.expect(0.U, "a new batch starts with clear error counts"))

          val hits = (0 until count).map { n =>
            Hit(
              n,
              rnd.nextBoolean(),
              rnd.nextLong() & 0xffffffffL,
              rnd.nextLong() & 0xffffffffL,
              rnd.nextLong() & 0xffffffffL,
              rnd.nextInt(1 << sys.core.triIndexBits),
              if (rnd.nextInt(4) == 0) rnd.nextInt(1 << ErrorFlags.width) else 0
            )
          }
          // Each core gets a random share, in a random order (cores finish rays out of order).
          val perCore = Array.fill(sys.cores)(mutable.Queue.empty[Hit])
          rnd.shuffle(hits).foreach(h => perCore(rnd.nextInt(sys.cores)).enqueue(h))
          val want = mutable.Map.empty[Long, BigInt] ++ hits.map(h => (base + 32L * h.number) -> h.record)
          val offering = Array.fill(sys.cores)(false)
          var cycle = 0
          while (want.nonEmpty && cycle < 5000) {
            for (c <- 0 until sys.cores) {
              offering(c) = perCore(c).nonEmpty && (offering(c) || rnd.nextInt(3) == 0)
              val port = dut.io.hits(c)
              port.valid.poke(offering(c).B)
              perCore(c).headOption.foreach { h =>
                port.bits.number.poke(h.number.U); port.bits.hit.poke(h.hit.B)
                port.bits.t.poke(h.t.U); port.bits.u.poke(h.u.U); port.bits.v.poke(h.v.U)
                port.bits.prim.poke(h.prim.U); port.bits.errors.poke(h.errors.U)
              }
            }
            val ready = rnd.nextInt(3) > 0
            dut.io.write.ready.poke(ready.B)
            if (ready && dut.io.write.valid.peek().litToBoolean) {
              val addr = dut.io.write.bits.addr.peek().litValue.toLong
              val data = dut.io.write.bits.data.peek().litValue
              val expected = want.remove(addr)
              assert(
                expected.isDefined,
                f"cycle $cycle: a record written at 0x$addr%x, not a pending ray's (duplicate or stray)"
              )
              assert(expected.get == data, f"cycle $cycle: record at 0x$addr%x is 0x$data%x, want 0x${expected.get}%x")
            }
            for (c <- 0 until sys.cores) if (offering(c) && dut.io.hits(c).ready.peek().litToBoolean) {
              perCore(c).dequeue(); offering(c) = false
            }
            dut.clock.step(); cycle += 1
          }
          assert(want.isEmpty, s"batch of $count: ${want.size} records never written after $cycle cycles")
          for (k <- 0 until ErrorFlags.width)
            dut.io.errCount(k).expect(hits.count(h => (h.errors >> k & 1) == 1).U, s"error count of flag $k")
          dut.io.broken.expect(false.B)
          dut.io.write.valid.expect(false.B, "a record left over")
        }
      }
    }
}
