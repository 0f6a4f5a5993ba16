package rtaccel.fetch

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.system.FieldDatapath
import rtaccel.testutil.{Backends, Seeded}

import scala.collection.mutable

class FetchBVHSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FetchBVH"

  private val cfg = AccelConfig(numRayIds = 4, stackDepth = 4, maxNodes = 256, maxTriangles = 256, maxLeafSize = 4)
  private def node(word0: Long, box: Int): BigInt =
    BigInt(word0) + (0 until 6).map(i => BigInt(box + i) << (64 + 32 * i)).sum

  private def idle(dut: FetchBVH[UInt]): Unit = {
    dut.io.rays.valid.poke(false.B); dut.io.free.valid.poke(false.B)
    dut.io.mem.req.ready.poke(true.B); dut.io.mem.resp.valid.poke(false.B)
    dut.io.enter.ready.poke(true.B); dut.io.out.ready.poke(true.B)
  }
  private def offer(dut: FetchBVH[UInt], number: Int, shadow: Boolean): Unit = {
    dut.io.rays.valid.poke(true.B)
    dut.io.rays.bits.number.poke(number.U)
    dut.io.rays.bits.shadow.poke(shadow.B)
    val r = dut.io.rays.bits.ray
    for (a <- 0 until 3) { r.origin(a).poke((number * 16 + a).U); r.dir(a).poke((if (a == 1) 0x80000000L + 5 else 5L).U) }
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
    dut.io.mem.resp.valid.poke(true.B); dut.io.mem.resp.bits.tag.poke(tag.U); dut.io.mem.resp.bits.data.poke(node(1, box).U)
    dut.clock.step()
    dut.io.mem.resp.valid.poke(false.B)
    tag
  }

  it should "fetch the root once, hold rays until it arrives, and write each ray before it enters" in Seeded("FetchBVH.root") { rnd =>
    test(new FetchBVH(cfg, FieldDatapath)).withAnnotations(Backends.treadle) { dut =>
      idle(dut)
      dut.io.nodeBase.poke(0x400.U)
      offer(dut, 0, shadow = false)
      answerRoot(dut, 0x400, box = 100)
      val entered = mutable.Set.empty[Int]
      val started = mutable.Map.empty[Int, Int] // ID -> ray number
      var numberNext = 0
      var requests = 0
      var pendingFree: Option[Int] = None
      for (cycle <- 0 until 400) {
        // Random back-pressure on both outputs; free IDs of rays that went out.
        dut.io.enter.ready.poke(rnd.nextBoolean().B); dut.io.out.ready.poke(rnd.nextBoolean().B)
        offer(dut, numberNext, shadow = numberNext % 3 == 0)
        if (dut.io.mem.req.valid.peek().litToBoolean) requests += 1
        if (dut.io.rays.ready.peek().litToBoolean) {
          dut.io.started.valid.expect(true.B)
          val id = dut.io.started.bits.peek().litValue.toInt
          assert(!started.contains(id), s"cycle $cycle: ID $id handed to two rays")
          started(id) = numberNext
          numberNext += 1
        }
        if (dut.io.enter.valid.peek().litToBoolean && dut.io.enter.ready.peek().litToBoolean)
          entered += dut.io.enter.bits.rayId.peek().litValue.toInt
        val freeNow = if (dut.io.out.valid.peek().litToBoolean && dut.io.out.ready.peek().litToBoolean) {
          val t = dut.io.out.bits.token
          val id = t.rayId.peek().litValue.toInt
          assert(entered.remove(id), s"cycle $cycle: ray $id went to the root before its RayBuffer write")
          t.nodeIdx.expect(0.U); t.sp.expect(0.U)
          t.dirNeg(0).expect(false.B); t.dirNeg(1).expect(true.B)
          t.shadow.expect((started(id) % 3 == 0).B, s"ray ${started(id)} shadow flag")
          dut.io.out.bits.root.boxMin(0).expect(100.U, "the on-chip root")
          dut.io.numberId.poke(id.U)
          dut.io.number.expect(started(id).U, s"host number of ID $id")
          Some(id)
        } else None
        // The output stage frees an ID later; here in the next cycle.
        dut.io.free.valid.poke(pendingFree.isDefined.B)
        pendingFree.foreach(id => dut.io.free.bits.poke(id.U))
        dut.clock.step()
        pendingFree.foreach(started.remove)
        pendingFree = freeNow
      }
      assert(requests == 0, s"$requests node requests after the root: new rays must not fetch it again")
      assert(numberNext > 40, s"only $numberNext rays entered in 400 cycles")
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
      dut.io.mem.resp.valid.poke(true.B); dut.io.mem.resp.bits.tag.poke(oldTag.U); dut.io.mem.resp.bits.data.poke(node(1, 7).U)
      dut.clock.step()
      dut.io.mem.resp.valid.poke(false.B)
      dut.io.rays.ready.expect(false.B, "a late answer for the old base is not the new root")
      dut.io.mem.req.ready.poke(true.B)
      val newTag = answerRoot(dut, 0x800, box = 200)
      assert(newTag != oldTag, "the refetch carries a new generation tag")
      offer(dut, 9, shadow = false)
      dut.io.rays.ready.expect(true.B)
      dut.clock.step()
      dut.io.rays.valid.poke(false.B)
      while (!dut.io.out.valid.peek().litToBoolean) dut.clock.step()
      dut.io.out.bits.root.boxMin(0).expect(200.U, "rays see the new scene's root")
    }
  }
}
