package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.sim.axi.SparseMemory
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** RayDma alone, against a Scala memory holding the batch's ray records: the
  * memory takes requests with random ready and answers each after a random
  * delay, in any order (a random due one first); the ray port takes rays with
  * random ready. The scoreboard is the batch: every record comes out exactly
  * once with its words, shadow bit and number, a record with an unknown flag
  * bit comes out with a quiet-NaN origin x, each block is read once, and no
  * more than `rayBlockTags` blocks are ever in flight, each under its own tag.
  */
class RayDmaSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RayDma"

  it should "hand out every ray of a batch once, whatever order memory answers in (random back-pressure)" in
    Seeded("RayDma.batches") { rnd =>
      // The default tags, and 2 (the formal system check's): a batch of more blocks than tags reuses each tag.
      for (tags <- Seq(SystemConfig().rayBlockTags, 2)) {
        val sys = SystemConfig(cores = 1, rayBlockTags = tags)
        val block = sys.rayBlockBytes
        test(new RayDma(sys)).withAnnotations(Backends.treadle) { dut =>
          for ((base, count) <- Seq((0x40000L, 23), (0x1000000L, 64), (0x3000L, 1), (0x80000L, 4 * tags + 7))) {
            val mem = new SparseMemory
            val words = Array.tabulate(count, 12)((_, _) => rnd.nextLong() & 0xffffffffL)
            for (n <- 0 until count) {
              words(n)(8) = rnd.nextInt(8) match { case 0 => 1L; case 1 => 1L << (1 + rnd.nextInt(31)); case _ => 0L }
              for (k <- 0 until 12) mem.writeLE(base + 48L * n + 4 * k, 4, BigInt(words(n)(k)))
            }
            dut.io.rayBase.poke(base.U); dut.io.rayCount.poke(count.U)
            dut.io.start.poke(true.B); dut.clock.step(); dut.io.start.poke(false.B)

            val pending = mutable.Set.empty[Int] ++ (0 until count)
            val blocksWant = mutable.Set.empty[Long] ++ (0 until (count + sys.raysPerBlock - 1) / sys.raysPerBlock).map(
              base + block.toLong * _
            )
            val inFlight = mutable.ArrayBuffer.empty[(Int, Long, Int)] // (tag, address, cycle due)
            var cycle = 0
            while ((pending.nonEmpty || inFlight.nonEmpty) && cycle < 5000) {
              val reqReady = rnd.nextInt(3) > 0
              dut.io.mem.req.ready.poke(reqReady.B)
              val due = inFlight.filter(_._3 <= cycle)
              val answer = if (due.nonEmpty && rnd.nextBoolean()) Some(due(rnd.nextInt(due.size))) else None
              dut.io.mem.resp.valid.poke(answer.isDefined.B)
              answer.foreach { case (tag, addr, _) =>
                dut.io.mem.resp.bits.tag.poke(tag.U)
                dut.io.mem.resp.bits.data.poke(mem.readLE(addr, block).U)
              }
              dut.io.mem.resp.ready.expect(true.B, "the block port never back-pressures memory")
              val raysReady = rnd.nextInt(3) > 0
              dut.io.rays.ready.poke(raysReady.B)

              if (raysReady && dut.io.rays.valid.peek().litToBoolean) {
                val r = dut.io.rays.bits
                val n = r.number.peek().litValue.toInt
                assert(pending.remove(n), s"cycle $cycle: ray $n handed out twice, or not in the batch of $count")
                val w = words(n)
                val invalid = (w(8) >> 1) != 0
                r.ray.origin(0).expect(
                  (if (invalid) RayDma.QuietNaN else w(0)).U,
                  s"ray $n origin x (flags 0x${w(8).toHexString})"
                )
                r.ray.origin(1).expect(w(1).U, s"ray $n origin y"); r.ray.origin(2).expect(w(2).U, s"ray $n origin z")
                for (k <- 0 until 3) r.ray.dir(k).expect(w(3 + k).U, s"ray $n dir $k")
                r.ray.tmin.expect(w(6).U, s"ray $n tmin"); r.ray.tmax.expect(w(7).U, s"ray $n tmax")
                r.shadow.expect(((w(8) & 1) == 1).B, s"ray $n shadow")
              }
              if (reqReady && dut.io.mem.req.valid.peek().litToBoolean) {
                val addr = dut.io.mem.req.bits.addr.peek().litValue.toLong
                val tag = dut.io.mem.req.bits.tag.peek().litValue.toInt
                assert(blocksWant.remove(addr), f"cycle $cycle: block at 0x$addr%x read twice or outside the batch")
                assert(!inFlight.exists(_._1 == tag), s"cycle $cycle: tag $tag reused while in flight")
                assert(
                  inFlight.size < sys.rayBlockTags,
                  s"cycle $cycle: more than ${sys.rayBlockTags} blocks in flight"
                )
                inFlight += ((tag, addr, cycle + 1 + rnd.nextInt(20)))
              }
              answer.foreach(a => inFlight -= a)
              dut.clock.step(); cycle += 1
              dut.io.broken.expect(false.B, s"cycle $cycle: broken")
            }
            assert(
              pending.isEmpty && blocksWant.isEmpty,
              s"batch of $count after $cycle cycles: rays ${pending.toSeq.sorted.take(10)} and blocks $blocksWant never came"
            )
            for (_ <- 0 until 4) {
              dut.io.rays.valid.expect(false.B, "a ray beyond the batch"); dut.io.mem.req.valid.expect(false.B);
              dut.clock.step()
            }
          }
        }
      }
    }
}
