package rtaccel.traversal

import chisel3._
import chiseltest._
import rtaccel.system.RamQueue
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded
import rtaccel.AccelConfig
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{Backends, FieldDatapath}

import scala.collection.mutable

class InitTraversalSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "InitTraversal"

  private val cfg = AccelConfig(
    numRayIds = 4,
    stackDepth = 4,
    maxNodes = 256,
    maxTriangles = 256,
    maxLeafSize = 4,
    layout = BvhLayout.Wide(2)
  )

  private def pokeIn(dut: InitTraversal[UInt], valid: Boolean, id: Int): Unit = {
    dut.io.in.valid.poke(valid.B)
    val p = dut.io.in.bits
    p.rayId.poke(id.U); p.shadow.poke((id % 2 == 1).B)
    p.ray.statics.poke((0x100 + id).U); p.ray.tmax.poke((0x3f000000L + id).U)
    for (a <- 0 until 3) p.ray.dirNeg(a).poke((((id >> a) & 1) == 1).B)
    p.ray.errors.poke((id % 3).U)
  }

  it should "write each ray to the RayBuffer before it goes to the root, in order, under back-pressure" in Seeded(
    "InitTraversal.order"
  ) { rnd =>
    test(new InitTraversal(cfg, FieldDatapath.gen)).withAnnotations(Backends.treadle) { dut =>
      for (s <- 0 until 2; i <- 0 until 3) {
        dut.io.root.slots(s).boxMin.get(i).poke((10 * s + i).U); dut.io.root.slots(s).present.poke(true.B)
      }
      val free = mutable.Queue.from(0 until cfg.numRayIds)
      val expected = mutable.Queue.empty[Int] // IDs in arrival order, not yet handed over
      val toWrite = mutable.Queue.empty[Int] // IDs in arrival order, not yet written
      val written = mutable.Map.empty[Int, Int] // ID -> cycle of its RayBuffer write
      val returning = mutable.Queue.empty[(Int, Int)] // (cycle, ID): back to the free list later
      var out = 0
      for (cycle <- 0 until 600) {
        val send = free.nonEmpty && rnd.nextInt(3) != 0
        val id = if (send) free.dequeue() else 0
        pokeIn(dut, send, id)
        if (send) { expected.enqueue(id); toWrite.enqueue(id) }
        dut.io.enter.ready.poke(rnd.nextBoolean().B)
        dut.io.out.ready.poke(rnd.nextBoolean().B)
        if (dut.io.enter.valid.peek().litToBoolean && dut.io.enter.ready.peek().litToBoolean) {
          val e = dut.io.enter.bits
          val wid = e.rayId.peek().litValue.toInt
          assert(wid == toWrite.dequeue(), s"cycle $cycle: RayBuffer write for ray $wid out of arrival order")
          e.statics.expect((0x100 + wid).U); e.tmax.expect((0x3f000000L + wid).U)
          assert(!written.contains(wid), s"cycle $cycle: ray $wid written twice")
          written(wid) = cycle
        }
        if (dut.io.out.valid.peek().litToBoolean && dut.io.out.ready.peek().litToBoolean) {
          val t = dut.io.out.bits.token
          val oid = t.rayId.peek().litValue.toInt
          assert(oid == expected.head, s"cycle $cycle: ray $oid left before ${expected.head}")
          // The box stage reads the RayBuffer in the cycle it takes the ray: the write must be older.
          val at =
            written.remove(oid).getOrElse(fail(s"cycle $cycle: ray $oid went to the root before its RayBuffer write"))
          assert(at < cycle, s"cycle $cycle: ray $oid handed over in the cycle of its RayBuffer write")
          t.nodeIdx.expect(0.U); t.sp.expect(0.U)
          t.shadow.expect((oid % 2 == 1).B); t.errors.expect((oid % 3).U)
          for (a <- 0 until 3) t.dirNeg(a).expect((((oid >> a) & 1) == 1).B)
          for (s <- 0 until 2; i <- 0 until 3)
            dut.io.out.bits.root.slots(s).boxMin.get(i).expect((10 * s + i).U, "the on-chip root")
          expected.dequeue()
          returning.enqueue((cycle + 1 + rnd.nextInt(10), oid))
          out += 1
        }
        dut.io.broken.expect(false.B)
        dut.clock.step()
        while (returning.headOption.exists(_._1 <= cycle)) free.enqueue(returning.dequeue()._2)
      }
      assert(out > 100, s"only $out rays entered traversal in 600 cycles")
    }
  }

  it should "flag a prepared ray that finds its queue full (more rays than IDs: a broken ID pool)" in {
    test(new InitTraversal(cfg, FieldDatapath.gen)).withAnnotations(Backends.treadle) { dut =>
      dut.io.enter.ready.poke(false.B); dut.io.out.ready.poke(false.B)
      // The queue (a RamQueue of numRayIds) holds a few more than numRayIds; one more than it holds is flagged.
      val holds = RamQueue.capacity(cfg.numRayIds)
      for (id <- 0 to holds) {
        dut.io.broken.expect(false.B, s"after $id rays")
        pokeIn(dut, valid = true, id % cfg.numRayIds)
        dut.clock.step()
      }
      dut.io.broken.expect(true.B, s"${holds + 1} rays in a queue that holds $holds")
    }
  }
}
