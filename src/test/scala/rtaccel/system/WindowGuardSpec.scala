package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.Axi4Params

/** WindowGuard alone: a burst inside the window passes unchanged in the same
  * cycle; one outside is not issued and is answered inside (zero-data R beats
  * with its ID and rlast; one B for a write, its W beats dropped).
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

  it should "pass bursts inside the window and answer refused ones itself" in {
    test(new WindowGuard(p)) { c =>
      idle(c)
      // Inside: passes the same cycle.
      c.io.in.ar.valid.poke(true.B); c.io.in.ar.bits.addr.poke(0x1fc0.U); c.io.in.ar.bits.len.poke(0.U);
      c.io.in.ar.bits.id.poke(3.U)
      c.io.out.ar.valid.expect(true.B); c.io.in.ar.ready.expect(true.B); c.io.refused.expect(false.B)
      c.clock.step()
      // Its beat comes back; then a burst ending past the limit is refused.
      c.io.out.r.valid.poke(true.B); c.io.out.r.bits.id.poke(3.U); c.io.out.r.bits.last.poke(true.B);
      c.io.out.r.bits.data.poke(7.U)
      c.io.in.ar.bits.addr.poke(0x1fc0.U); c.io.in.ar.bits.len.poke(1.U); c.io.in.ar.bits.id.poke(5.U)
      c.io.in.r.valid.expect(true.B); c.io.in.r.bits.data.expect(7.U)
      c.io.out.ar.valid.expect(false.B); c.io.in.ar.ready.expect(true.B); c.io.refused.expect(true.B)
      c.io.refusedAddr.expect(0x1fc0.U)
      c.clock.step()
      c.io.out.r.valid.poke(false.B); c.io.in.ar.valid.poke(false.B)
      for (beat <- 0 until 2) {
        c.io.in.r.valid.expect(true.B, s"fake beat $beat"); c.io.in.r.bits.id.expect(5.U);
        c.io.in.r.bits.data.expect(0.U)
        c.io.in.r.bits.last.expect((beat == 1).B); c.io.in.r.bits.resp.expect(0.U)
        c.clock.step()
      }
      c.io.in.r.valid.expect(false.B)
      // A write below the base: AW not issued, W dropped, one B.
      c.io.in.aw.valid.poke(true.B); c.io.in.aw.bits.addr.poke(0xfc0.U); c.io.in.aw.bits.len.poke(0.U);
      c.io.in.aw.bits.id.poke(0.U)
      c.io.in.w.valid.poke(true.B); c.io.in.w.bits.last.poke(true.B)
      c.io.out.aw.valid.expect(false.B); c.io.out.w.valid.expect(false.B); c.io.in.w.ready.expect(true.B);
      c.io.in.aw.ready.expect(true.B)
      c.clock.step()
      c.io.in.aw.valid.poke(false.B); c.io.in.w.valid.poke(false.B)
      var n = 0
      while (!c.io.in.b.valid.peek().litToBoolean && n < 5) { c.clock.step(); n += 1 }
      c.io.in.b.valid.expect(true.B, "the refused write's B")
      c.clock.step()
      c.io.in.b.valid.expect(false.B)
      // Limit 0: the whole space.
      c.io.limit.poke(0.U); c.io.base.poke(0.U)
      c.io.in.ar.valid.poke(true.B); c.io.in.ar.bits.addr.poke(0xffffffc0L.U); c.io.in.ar.bits.len.poke(0.U)
      c.io.out.ar.valid.expect(true.B)
    }
  }
}
