package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.Axi4Params
import rtaccel.testutil.Seeded

/** WindowGuard alone: a burst inside the window passes unchanged two cycles
  * later (its register slice and decision register), one per cycle, none lost
  * while m_axi stalls; one outside is not issued and is answered inside
  * (zero-data R beats with its ID and rlast; one B for a write, its W beats
  * dropped), and counted a cycle after its refusal; a burst that arrives as
  * the window changes is judged against the new window.
  */
class WindowGuardSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "WindowGuard"
  private val p = Axi4Params(addrBits = 32, dataBits = 512, idBits = 6)

  private def idle(c: WindowGuard): Unit = {
    c.io.in.ar.valid.poke(false.B); c.io.in.aw.valid.poke(false.B); c.io.in.w.valid.poke(false.B)
    c.io.in.r.ready.poke(true.B); c.io.in.b.ready.poke(true.B)
    c.io.out.ar.ready.poke(true.B); c.io.out.aw.ready.poke(true.B); c.io.out.w.ready.poke(true.B)
    c.io.out.r.valid.poke(false.B); c.io.out.b.valid.poke(false.B)
    c.io.base.poke(0x1000.U); c.io.limit.poke(0x2000.U)
  }
  private def ar(c: WindowGuard, addr: BigInt, len: Int, id: Int): Unit = {
    c.io.in.ar.valid.poke(true.B); c.io.in.ar.bits.addr.poke(addr.U); c.io.in.ar.bits.len.poke(len.U)
    c.io.in.ar.bits.id.poke(id.U)
  }
  private def aw(c: WindowGuard, addr: BigInt, len: Int, id: Int): Unit = {
    c.io.in.aw.valid.poke(true.B); c.io.in.aw.bits.addr.poke(addr.U); c.io.in.aw.bits.len.poke(len.U)
    c.io.in.aw.bits.id.poke(id.U)
  }

  /** Out of reset the guard takes the window into its own copy before it decides a burst: two cycles. */
  private def settle(c: WindowGuard): Unit = c.clock.step(2)

  it should "pass bursts inside the window two cycles later and answer refused ones itself" in {
    test(new WindowGuard(p)) { c =>
      idle(c)
      settle(c)
      // Inside, ending exactly at the limit: taken at once, decided the next cycle, offered on m_axi the one after.
      ar(c, 0x1fc0, 0, 3)
      c.io.in.ar.ready.expect(true.B); c.io.out.ar.valid.expect(false.B)
      c.clock.step()
      c.io.in.ar.valid.poke(false.B)
      c.io.out.ar.valid.expect(false.B)
      c.clock.step()
      c.io.out.ar.valid.expect(true.B); c.io.out.ar.bits.addr.expect(0x1fc0.U); c.io.out.ar.bits.id.expect(3.U)
      c.io.refused.expect(0.U)
      c.clock.step()
      // Its beat comes back; meanwhile a burst ending a beat past the limit enters the slice.
      c.io.out.r.valid.poke(true.B); c.io.out.r.bits.id.poke(3.U); c.io.out.r.bits.last.poke(true.B)
      c.io.out.r.bits.data.poke(7.U)
      ar(c, 0x1fc0, 1, 5)
      c.io.in.r.valid.expect(true.B); c.io.in.r.bits.data.expect(7.U)
      c.clock.step()
      c.io.out.r.valid.poke(false.B); c.io.in.ar.valid.poke(false.B)
      // At the slice's head, being decided.
      c.io.out.ar.valid.expect(false.B); c.io.refused.expect(0.U)
      c.clock.step()
      // In the decision register: refused, not offered; counted the next cycle, with its address.
      c.io.out.ar.valid.expect(false.B); c.io.refused.expect(0.U)
      c.clock.step()
      c.io.refused.expect(1.U); c.io.refusedAddr.expect(0x1fc0.U)
      for (beat <- 0 until 2) {
        c.io.in.r.valid.expect(true.B, s"fake beat $beat"); c.io.in.r.bits.id.expect(5.U)
        c.io.in.r.bits.data.expect(0.U)
        c.io.in.r.bits.last.expect((beat == 1).B); c.io.in.r.bits.resp.expect(0.U)
        c.clock.step()
        c.io.refused.expect(0.U)
      }
      c.io.in.r.valid.expect(false.B)
      // A write below the base, its W beat offered with its AW: AW not issued, W dropped, one B.
      aw(c, 0xfc0, 0, 0)
      c.io.in.w.valid.poke(true.B); c.io.in.w.bits.last.poke(true.B)
      c.io.in.aw.ready.expect(true.B); c.io.in.w.ready.expect(false.B, "W waits until its AW is decided")
      c.clock.step()
      c.io.in.aw.valid.poke(false.B)
      c.io.out.aw.valid.expect(false.B); c.io.in.w.ready.expect(false.B, "W waits while its AW is decided")
      c.clock.step()
      c.io.out.aw.valid.expect(false.B); c.io.out.w.valid.expect(false.B); c.io.in.w.ready.expect(true.B)
      c.clock.step()
      c.io.in.w.valid.poke(false.B)
      var n = 0
      while (!c.io.in.b.valid.peek().litToBoolean && n < 5) { c.clock.step(); n += 1 }
      c.io.in.b.valid.expect(true.B, "the refused write's B")
      c.clock.step()
      c.io.in.b.valid.expect(false.B)
      // Limit 0: the whole space, up to its last line, once the guard has taken the new window.
      c.io.limit.poke(0.U); c.io.base.poke(0.U)
      ar(c, BigInt(0xffffffc0L), 0, 1)
      c.clock.step()
      c.io.in.ar.valid.poke(false.B)
      var k = 0
      while (!c.io.out.ar.valid.peek().litToBoolean && k < 6) { c.clock.step(); k += 1 }
      c.io.out.ar.valid.expect(true.B)
      c.io.refused.expect(0.U)
    }
  }

  it should "judge a burst that arrives as the window changes against the new window" in {
    test(new WindowGuard(p)) { c =>
      idle(c)
      settle(c)
      // Inside the old window [0x1000, 0x2000), outside the new [0x1000, 0x1800).
      c.io.limit.poke(0x1800.U)
      ar(c, 0x1c00, 0, 2)
      c.clock.step()
      c.io.in.ar.valid.poke(false.B)
      var refused = 0
      for (_ <- 0 until 8) {
        c.io.out.ar.valid.expect(false.B, "a burst outside the new window offered")
        refused += c.io.refused.peek().litValue.toInt
        c.clock.step()
      }
      assert(refused == 1, s"refused $refused times")
    }
  }

  it should "refuse a read and a write in the same cycle and count both" in {
    test(new WindowGuard(p)) { c =>
      idle(c)
      settle(c)
      ar(c, 0x2000, 0, 1); aw(c, 0x800, 0, 2)
      c.io.in.w.valid.poke(true.B); c.io.in.w.bits.last.poke(true.B)
      c.clock.step()
      c.io.in.ar.valid.poke(false.B); c.io.in.aw.valid.poke(false.B)
      c.io.out.ar.valid.expect(false.B); c.io.out.aw.valid.expect(false.B)
      c.clock.step()
      c.io.out.ar.valid.expect(false.B); c.io.out.aw.valid.expect(false.B)
      c.clock.step()
      c.io.in.w.valid.poke(false.B)
      c.io.refused.expect(2.U); c.io.refusedAddr.expect(0x2000.U)
    }
  }

  it should "keep every burst, in order, one per cycle, while m_axi stalls at random" in {
    Seeded("WindowGuard.stalls") { rnd =>
      test(new WindowGuard(p)) { c =>
        idle(c)
        val n = 200
        val sent = (0 until n).map(i => 0x1000 + 64 * (i % 64))
        var next = 0
        val seen = collection.mutable.ArrayBuffer.empty[Int]
        var cycles = 0
        while (seen.size < n && cycles < 20 * n) {
          val offer = next < n && rnd.nextInt(4) != 0
          val ready = rnd.nextInt(3) != 0
          if (offer) ar(c, sent(next), 0, next % 64) else c.io.in.ar.valid.poke(false.B)
          c.io.out.ar.ready.poke(ready.B)
          if (c.io.out.ar.valid.peek().litToBoolean && ready) seen += c.io.out.ar.bits.addr.peek().litValue.toInt
          if (offer && c.io.in.ar.ready.peek().litToBoolean) next += 1
          c.io.refused.expect(0.U)
          c.clock.step(); cycles += 1
        }
        assert(seen.toSeq == sent, s"bursts lost, duplicated or reordered: ${seen.size} of $n seen")
        // Full throughput: with m_axi always ready and a burst always on offer, one burst per cycle.
        c.io.out.ar.ready.poke(true.B)
        val m = 16
        for (i <- 0 to m + 1) {
          if (i < m) { ar(c, 0x1000 + 64 * i, 0, i); c.io.in.ar.ready.expect(true.B, s"burst $i waits") }
          else c.io.in.ar.valid.poke(false.B)
          if (i > 1) { c.io.out.ar.valid.expect(true.B, s"cycle $i"); c.io.out.ar.bits.id.expect((i - 2).U) }
          c.clock.step()
        }
        c.io.out.ar.valid.expect(false.B)
      }
    }
  }
}
