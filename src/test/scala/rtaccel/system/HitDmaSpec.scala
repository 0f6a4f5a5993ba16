package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.ErrorFlags
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** HitDma alone: each core offers its share of a batch's hits with seeded
  * random valid (held until taken), the write port takes lines with random
  * ready. The scoreboard is the batch, ray by ray: every ray's record is
  * written exactly once, in a line at HIT_BASE + 64 * (number / 2), in its
  * half (number mod 2) with that half's strobes, with the documented bytes;
  * the error counters count the batch's flags; a second batch starts clean.
  * Hits in number order pair every neighbour (ceil(count / 2) lines); in
  * random order through a small pair buffer, slots conflict and the batch's
  * end flushes the hits left waiting.
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

  /** Runs batches of (hit base, count) through HitDma; returns the lines written per batch. A `stopped` batch hands
    * out only a random subset of its rays (RayDma's block order), and `stop` rises at a random cycle. */
  private def batches(
      sys: SystemConfig,
      rnd: scala.util.Random,
      shuffle: Boolean,
      runs: Seq[(Long, Int)],
      stopped: Boolean = false
  ): Seq[Int] = {
    val lines = mutable.ArrayBuffer.empty[Int]
    test(new HitDma(sys)).withAnnotations(Backends.treadle) { dut =>
      for ((base, count) <- runs) {
        dut.io.hitBase.poke(base.U); dut.io.rayCount.poke(count.U)
        dut.io.stop.poke(false.B); dut.io.issued.poke(0.U)
        dut.io.start.poke(true.B); dut.clock.step(); dut.io.start.poke(false.B)
        dut.io.errCount.foreach(_.expect(0.U, "a new batch starts with clear error counts"))

        // A stopped batch: an odd number of rays handed out, so some line's partner never comes.
        val handedOut =
          if (stopped) rnd.shuffle((0 until count).toList).take(2 * rnd.nextInt(count / 2) + 1).sorted
          else 0 until count
        val stopAt = rnd.nextInt(3 * handedOut.size)
        val hits = handedOut.map { n =>
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
        (if (shuffle) rnd.shuffle(hits) else hits).foreach(h => perCore(rnd.nextInt(sys.cores)).enqueue(h))
        var written = 0
        val want = mutable.Map.empty[Long, BigInt] ++ hits.map(h => (base + 32L * h.number) -> h.record)
        val offering = Array.fill(sys.cores)(false)
        var cycle = 0
        while (want.nonEmpty && cycle < 5000) {
          if (stopped && cycle == stopAt) { dut.io.stop.poke(true.B); dut.io.issued.poke(handedOut.size.U) }
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
            val halves = dut.io.write.bits.halves.peek().litValue.toInt
            assert(addr % 64 == 0 && halves >= 1 && halves <= 3, f"cycle $cycle: line at 0x$addr%x with halves $halves")
            for (k <- 0 until 2 if (halves >> k & 1) == 1) {
              val at = addr + 32 * k
              val got = (data >> (256 * k)) & ((BigInt(1) << 256) - 1)
              val expected = want.remove(at)
              assert(
                expected.isDefined,
                f"cycle $cycle: a record written at 0x$at%x, not a pending ray's (duplicate or stray)"
              )
              assert(expected.get == got, f"cycle $cycle: record at 0x$at%x is 0x$got%x, want 0x${expected.get}%x")
            }
            written += 1
          }
          for (c <- 0 until sys.cores) if (offering(c) && dut.io.hits(c).ready.peek().litToBoolean) {
            perCore(c).dequeue(); offering(c) = false
          }
          dut.clock.step(); cycle += 1
        }
        assert(
          want.isEmpty,
          s"batch of $count (${handedOut.size} handed out): ${want.size} records never written after $cycle cycles"
        )
        for (k <- 0 until ErrorFlags.width)
          dut.io.errCount(k).expect(hits.count(h => (h.errors >> k & 1) == 1).U, s"error count of flag $k")
        dut.io.broken.expect(false.B)
        dut.io.write.valid.expect(false.B, "a record left over")
        lines += written
      }
    }
    lines.toSeq
  }

  private val twoBatches = Seq((0x10000000L, 157), (0x2000L, 61))

  it should "write every hit of a batch once, in its line's half, under random back-pressure (2 cores)" in
    Seeded("HitDma.batches") { rnd =>
      val lines = batches(SystemConfig(cores = 2), rnd, shuffle = true, twoBatches)
      for (((_, n), l) <- twoBatches.zip(lines))
        assert(l >= (n + 1) / 2 && l <= n, s"batch of $n: $l lines")
    }

  it should "pair every neighbour when hits come in number order: ceil(count / 2) lines, the odd last alone" in
    Seeded("HitDma.inOrder") { rnd =>
      val lines = batches(SystemConfig(cores = 1), rnd, shuffle = false, twoBatches)
      assert(lines == twoBatches.map(b => (b._2 + 1) / 2), s"lines per batch $lines")
    }

  it should "write every hit once through a 2-slot pair buffer (conflicts, and the flush at the batch's end)" in
    Seeded("HitDma.smallBuffer") { rnd =>
      val lines = batches(SystemConfig(cores = 2, hitPairSlots = Some(2)), rnd, shuffle = true, twoBatches)
      println(s"HitDma, 2 pair slots, random order: lines per batch $lines for ${twoBatches.map(_._2)} hits")
      // More lines than pairs: hits left alone by a slot held for another pair (the path the flush ends).
      for (((_, n), l) <- twoBatches.zip(lines)) assert(l > (n + 1) / 2 && l <= n, s"batch of $n: $l lines")
    }

  it should "flush the hits left waiting when a batch stops with a line's partner never handed out" in
    Seeded("HitDma.stopped") { rnd =>
      val lines =
        batches(SystemConfig(cores = 2, hitPairSlots = Some(8)), rnd, shuffle = true, twoBatches, stopped = true)
      println(s"HitDma, stopped batches: lines per batch $lines")
    }
}
