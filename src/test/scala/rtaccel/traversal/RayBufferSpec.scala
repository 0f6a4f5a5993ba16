package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

import scala.collection.mutable

class RayBufferSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RayBuffer"

  private val cfg = AccelConfig(numRayIds = 8)
  private def dut() = new RayBuffer(cfg, UInt(40.W), readers = 2)

  it should "alternate between new rays and tmax updates under contention" in {
    test(dut()).withAnnotations(Backends.treadle) { dut =>
      val grants = mutable.ArrayBuffer.empty[String]
      for (cycle <- 0 until 20) {
        dut.io.enter.valid.poke(true.B)
        dut.io.enter.bits.rayId.poke((cycle % 8).U)
        dut.io.enter.bits.statics.poke(cycle.U)
        dut.io.enter.bits.tmax.poke(cycle.U)
        dut.io.update.valid.poke(true.B)
        dut.io.update.bits.rayId.poke(((cycle + 4) % 8).U)
        dut.io.update.bits.tmax.poke((1000 + cycle).U)
        val e = dut.io.enter.ready.peek().litToBoolean
        val u = dut.io.update.ready.peek().litToBoolean
        assert(e != u, s"cycle $cycle: exactly one writer must be granted (enter=$e update=$u)")
        grants += (if (e) "enter" else "update")
        dut.clock.step()
      }
      assert(grants.sliding(2).forall(w => w(0) != w(1)), s"grants not alternating: $grants")
    }
  }

  it should "return what was last written for each ray, on every read port" in Seeded("RayBuffer.random") { rnd =>
    test(dut()).withAnnotations(Backends.treadle) { dut =>
      val statics = mutable.Map.empty[Int, BigInt]
      val tmax = mutable.Map.empty[Int, BigInt]
      var pendingReads = Seq.empty[(Int, Int)] // (port, ray) read last cycle
      for (cycle <- 0 until 3000) {
        for ((port, id) <- pendingReads) {
          dut.io.read(port).statics.expect(statics(id).U, s"cycle $cycle port $port ray $id statics")
          dut.io.read(port).tmax.expect(tmax(id).U, s"cycle $cycle port $port ray $id tmax")
        }
        val enterId = rnd.nextInt(8); val enterS = BigInt(40, rnd); val enterT = BigInt(32, rnd)
        val known = tmax.keys.toSeq
        val doUpdate = known.nonEmpty && rnd.nextBoolean()
        val updId = if (doUpdate) known(rnd.nextInt(known.size)) else 0
        val updT = BigInt(32, rnd)
        val doEnter = rnd.nextBoolean() && enterId != updId
        dut.io.enter.valid.poke(doEnter.B)
        dut.io.enter.bits.rayId.poke(enterId.U); dut.io.enter.bits.statics.poke(enterS.U);
        dut.io.enter.bits.tmax.poke(enterT.U)
        dut.io.update.valid.poke(doUpdate.B)
        dut.io.update.bits.rayId.poke(updId.U); dut.io.update.bits.tmax.poke(updT.U)
        // Read rays whose data will not change in this cycle's write.
        val reads = for (port <- 0 until 2; if known.nonEmpty && rnd.nextBoolean())
          yield (port, known(rnd.nextInt(known.size)))
        val safe = reads.filterNot { case (_, id) => (doEnter && id == enterId) || (doUpdate && id == updId) }
        for (port <- 0 until 2) {
          val r = safe.find(_._1 == port)
          dut.io.read(port).en.poke(r.isDefined.B)
          r.foreach { case (_, id) => dut.io.read(port).rayId.poke(id.U) }
        }
        val enterFire = doEnter && dut.io.enter.ready.peek().litToBoolean
        val updFire = doUpdate && dut.io.update.ready.peek().litToBoolean
        dut.clock.step()
        if (enterFire) { statics(enterId) = enterS; tmax(enterId) = enterT }
        if (updFire) tmax(updId) = updT
        pendingReads = safe
      }
    }
  }
}
