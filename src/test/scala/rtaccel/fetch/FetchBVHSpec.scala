package rtaccel.fetch

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.testutil.Seeded
import rtaccel.bvh.{BvhLayout, BvhNode}
import rtaccel.sim.{Backends, FieldDatapath}

import scala.collection.mutable

class FetchBVHSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FetchBVH"

  // A 4-wide layout: the root is a 128-byte record of four slots.
  private val cfg = AccelConfig(
    numRayIds = 4,
    stackDepth = 4,
    maxNodes = 256,
    maxTriangles = 256,
    maxLeafSize = 4,
    layout = BvhLayout.Wide(4)
  )

  /** Slots 0 and 1 inner children, 2 and 3 empty; slot s's box words are box + 8 s + i. */
  private def node(box: Int): BigInt = (0 until 4).map { s =>
    val word0 = if (s < 2) BigInt(0) else BigInt(BvhNode.EmptySlot)
    (word0 + (0 until 6).map(i => BigInt(box + 8 * s + i) << (64 + 32 * i)).sum) << (256 * s)
  }.sum
  private def expectRoot(dut: FetchBVH[UInt], box: Int, what: String): Unit =
    for (s <- 0 until 4) {
      dut.io.root.slots(s).present.expect((s < 2).B, s"$what: slot $s used")
      for (i <- 0 until 3) dut.io.root.slots(s).boxMin.get(i).expect((box + 8 * s + i).U, s"$what: slot $s min[$i]")
      for (i <- 0 until 3) dut.io.root.slots(s).boxMax.get(i).expect((box + 8 * s + 3 + i).U, s"$what: slot $s max[$i]")
    }

  private def idle(dut: FetchBVH[UInt]): Unit = {
    dut.io.rays.valid.poke(false.B); dut.io.free.valid.poke(false.B)
    dut.io.mem.req.ready.poke(true.B); dut.io.mem.resp.valid.poke(false.B)
  }
  private def offer(dut: FetchBVH[UInt], number: Int, shadow: Boolean): Unit = {
    dut.io.rays.valid.poke(true.B)
    dut.io.rays.bits.number.poke(number.U)
    dut.io.rays.bits.shadow.poke(shadow.B)
    val r = dut.io.rays.bits.ray
    for (a <- 0 until 3) {
      r.origin(a).poke((number * 16 + a).U); r.dir(a).poke((if (a == 1) 0x80000000L + 5 else 5L).U)
    }
    r.tmin.poke(0.U); r.tmax.poke(0x7f000000L.U)
  }

  /** Answers the one outstanding root request, checking its address. */
  private def answerRoot(dut: FetchBVH[UInt], base: Int, box: Int): Int = {
    var tag = -1
    for (_ <- 0 until 5 if tag < 0) {
      if (dut.io.mem.req.valid.peek().litToBoolean) {
        dut.io.mem.req.bits.addr.expect(base.U, "the root is node 0, at the scene base")
        tag = dut.io.mem.req.bits.tag.peek().litValue.toInt
      }
      dut.clock.step()
    }
    assert(tag >= 0, "no root request")
    dut.io.mem.req.valid.expect(false.B, "one root request only")
    dut.io.rays.ready.expect(false.B, "rays must wait for the root")
    dut.io.mem.resp.valid.poke(true.B); dut.io.mem.resp.bits.tag.poke(tag.U);
    dut.io.mem.resp.bits.data.poke(node(box).U)
    dut.clock.step()
    dut.io.mem.resp.valid.poke(false.B)
    tag
  }

  it should "fetch the root once, hold rays until it arrives, give each ray a fresh ID and prepare it" in Seeded(
    "FetchBVH.root"
  ) { rnd =>
    test(new FetchBVH(cfg, FieldDatapath)).withAnnotations(Backends.treadle) { dut =>
      idle(dut)
      dut.io.nodeBase.poke(0x400.U)
      offer(dut, 0, shadow = false)
      answerRoot(dut, 0x400, box = 100)
      expectRoot(dut, 100, "the on-chip root")
      val started = mutable.Map.empty[Int, Int] // ID -> ray number
      val startedAt = mutable.Map.empty[Int, Int] // ID -> cycle
      var numberNext = 0
      var requests = 0
      var prepared = 0
      var pendingFree = mutable.Queue.empty[(Int, Int)] // (cycle to free, ID)
      for (cycle <- 0 until 400) {
        // Random gaps in the offered rays; IDs come back a random while after their ray was prepared.
        val offering = rnd.nextInt(4) != 0
        if (offering) offer(dut, numberNext, shadow = numberNext % 3 == 0) else dut.io.rays.valid.poke(false.B)
        if (dut.io.mem.req.valid.peek().litToBoolean) requests += 1
        if (offering && dut.io.rays.ready.peek().litToBoolean) {
          dut.io.started.valid.expect(true.B)
          val id = dut.io.started.bits.peek().litValue.toInt
          assert(!started.contains(id), s"cycle $cycle: ID $id handed to two rays")
          started(id) = numberNext
          startedAt(id) = cycle
          numberNext += 1
        } else dut.io.started.valid.expect(false.B, s"cycle $cycle: started without a ray taken")
        if (dut.io.prepared.valid.peek().litToBoolean) {
          val p = dut.io.prepared.bits
          val id = p.rayId.peek().litValue.toInt
          assert(started.contains(id), s"cycle $cycle: prepared ray with ID $id, which no ray holds")
          assert(
            cycle - startedAt(id) == FieldDatapath.prepLatency,
            s"cycle $cycle: ray $id prepared ${cycle - startedAt(id)} cycles after entry"
          )
          p.shadow.expect((started(id) % 3 == 0).B, s"ray ${started(id)} shadow flag")
          p.ray.dirNeg(0).expect(false.B); p.ray.dirNeg(1).expect(true.B)
          dut.io.numberId.poke(id.U)
          dut.io.number.expect(started(id).U, s"host number of ID $id")
          prepared += 1
          pendingFree.enqueue((cycle + 1 + rnd.nextInt(20), id))
        }
        val due = pendingFree.headOption.filter(_._1 <= cycle)
        dut.io.free.valid.poke(due.isDefined.B)
        due.foreach { case (_, id) => dut.io.free.bits.poke(id.U) }
        dut.clock.step()
        due.foreach { case (_, id) => pendingFree.dequeue(); started.remove(id) }
      }
      assert(requests == 0, s"$requests node requests after the root: new rays must not fetch it again")
      assert(
        prepared > 40 && prepared >= numberNext - cfg.numRayIds,
        s"only $prepared of $numberNext rays prepared in 400 cycles"
      )
      dut.io.doubleFree.expect(false.B)
    }
  }

  it should "refetch the root when the scene base changes, ignoring a late answer for the old base" in {
    test(new FetchBVH(cfg, FieldDatapath)).withAnnotations(Backends.treadle) { dut =>
      idle(dut)
      dut.io.nodeBase.poke(0x400.U)
      dut.io.mem.req.ready.poke(false.B)
      dut.clock.step(2)
      dut.io.mem.req.ready.poke(true.B)
      val oldTag = dut.io.mem.req.bits.tag.peek().litValue.toInt
      dut.clock.step() // the old-base request goes out...
      dut.io.mem.req.ready.poke(false.B) // (memory busy: the refetch waits below)
      dut.io.nodeBase.poke(0x800.U) // ...and the scene changes before it is answered
      dut.clock.step()
      dut.io.mem.resp.valid.poke(true.B); dut.io.mem.resp.bits.tag.poke(oldTag.U);
      dut.io.mem.resp.bits.data.poke(node(7).U)
      dut.clock.step()
      dut.io.mem.resp.valid.poke(false.B)
      dut.io.rays.ready.expect(false.B, "a late answer for the old base is not the new root")
      dut.io.mem.req.ready.poke(true.B)
      val newTag = answerRoot(dut, 0x800, box = 200)
      assert(newTag != oldTag, "the refetch carries a new generation tag")
      offer(dut, 9, shadow = false)
      dut.io.rays.ready.expect(true.B)
      expectRoot(dut, 200, "rays see the new scene's root")
    }
  }

  it should "decode a quantized root two cycles after its answer, and drop it if the scene base changes in them" in {
    // 4q with grid box tests: the record with its slots' counts, then its words, are registered before the checks
    // (BvhNode.staged), so rays wait two cycles more; an answer whose decode cycles see a new base must not become
    // the new scene's root.
    val q = cfg.copy(layout = BvhLayout.Wide(4, quantized = true), boxTest = rtaccel.BoxTest.Grid)
    assert(BvhNode.staged(q) && !BvhNode.staged(cfg))
    val img = rtaccel.sim.mem.SyntheticImage(nodes = 4, tris = 4, new scala.util.Random(5), q.layout)
    val record = img.readLE(img.nodeAddr(0), q.layout.nodeBytes)
    test(new FetchBVH(q, FieldDatapath)).withAnnotations(Backends.treadle) { dut =>
      idle(dut)
      dut.io.nodeBase.poke(0x400.U)
      // Memory takes a request only here (ready otherwise low), so the request answered is the one read.
      dut.io.mem.req.ready.poke(false.B)
      def answer(): Int = {
        while (!dut.io.mem.req.valid.peek().litToBoolean) dut.clock.step()
        val tag = dut.io.mem.req.bits.tag.peek().litValue.toInt
        dut.io.mem.req.ready.poke(true.B)
        dut.clock.step()
        dut.io.mem.req.ready.poke(false.B)
        dut.io.mem.resp.valid.poke(true.B); dut.io.mem.resp.bits.tag.poke(tag.U)
        dut.io.mem.resp.bits.data.poke(record.U)
        dut.clock.step()
        dut.io.mem.resp.valid.poke(false.B)
        tag
      }
      // The base changes in the first decode cycle (the record's register), then in the second (the words').
      for ((changeAt, base) <- Seq((0, 0x800), (1, 0xc00))) {
        dut.clock.step()
        answer()
        offer(dut, 1, shadow = false)
        for (_ <- 0 until changeAt) {
          dut.io.rays.ready.expect(false.B, "the root's record is being decoded: rays wait")
          dut.clock.step()
        }
        dut.io.rays.ready.expect(false.B, "the root's words are being decoded: rays wait")
        dut.io.nodeBase.poke(base.U) // the scene changes in a decode cycle
        dut.clock.step()
        dut.io.rays.ready.expect(false.B, "the old base's root, decoded after the change, is not the new root")
        dut.clock.step(3)
        dut.io.rays.ready.expect(false.B, "no root until the new base's answer")
      }
      answer()
      dut.io.rays.ready.expect(false.B, "the new root is in its first decode cycle")
      dut.clock.step()
      dut.io.rays.ready.expect(false.B, "the new root is in its second decode cycle")
      dut.clock.step()
      dut.io.rays.ready.expect(true.B, "the new root is valid")
      for (s <- 0 until 4) {
        val words = img.readLE(img.nodeAddr(0), q.layout.nodeBytes)
        assert(dut.io.root.slots(s).qMin.isDefined)
        val planes = (0 until 3).map(p => ((words >> (8 * rtaccel.bvh.QuantNode.planeByte(4, p, s))) & 0xff).toInt)
        for (a <- 0 until 3) dut.io.root.slots(s).qMin.get(a).expect(planes(a).U, s"slot $s lo[$a]")
      }
    }
  }
}
