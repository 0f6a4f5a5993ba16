package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.AxiResp
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** AxiLiteRegs alone, against a Scala register file built from RegisterMap.
  * A master sends seeded random reads and writes (mapped and unmapped
  * addresses, random strobes), AW and W each after its own random delay, with
  * random ready on B and R; one write and one read are in progress at a time,
  * overlapping each other. The hardware inputs change every cycle. Checked:
  * every transaction gets exactly one response with the right resp and data,
  * rw and w1c values follow the writes and sets cycle by cycle, wo pulses last
  * the write's one cycle, and a _HI read returns what its _LO read latched.
  */
class AxiLiteRegsSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "AxiLiteRegs"

  private val regs = RegisterMap.regs
  private def byteMask(strb: Int): Long = (0 until 4).map(b => if ((strb >> b & 1) == 1) 0xffL << (8 * b) else 0L).sum

  it should "answer every access once and keep every register as the map says (random back-pressure)" in
    Seeded("AxiLiteRegs.random") { rnd =>
      test(new AxiLiteRegs).withAnnotations(Backends.treadle) { dut =>
        val n = regs.size
        val state = Array.tabulate(n)(i => regs(i).reset.getOrElse(0L)) // rw and w1c contents
        val shadow = Array.fill(n)(0L)
        val mapped = regs.map(_.offset).toSet
        def randomAddr(): Int = {
          val word =
            if (rnd.nextInt(5) > 0) regs(rnd.nextInt(n)).offset else 4 * rnd.nextInt(RegisterMap.SpaceBytes / 4)
          word | rnd.nextInt(4) // bits 1..0 are ignored
        }
        final case class Wr(
            addr: Int,
            data: Long,
            strb: Int,
            var awSent: Boolean = false,
            var wSent: Boolean = false,
            awDelay: Int,
            wDelay: Int
        )
        final case class Rd(addr: Int, delay: Int, var sent: Boolean = false, var want: Option[(Long, Int)] = None)
        var wr: Option[Wr] = None
        var rd: Option[Rd] = None
        var writes, reads = 0
        var lastWrite: Option[Wr] = None // the write whose AW and W are both in, waiting for its B to rise
        var prevW1c = state.clone(); var prevHw = Array.fill(n)(0L); var prevPulse = Array.fill(n)(0L)
        var cycle = 0
        while ((writes < 250 || reads < 250) && cycle < 20000) {
          // Hardware inputs: random for ro registers, rare set bits for w1c.
          val hw = Array.tabulate(n)(i =>
            regs(i).access match {
              case Access.W1c => if (rnd.nextInt(8) == 0) 1L << rnd.nextInt(2) else 0L
              case _          => rnd.nextLong() & 0xffffffffL
            }
          )
          for (i <- 0 until n) dut.io.hw(i).poke(hw(i).U)

          if (wr.isEmpty && writes < 250)
            wr = Some(Wr(
              randomAddr(),
              rnd.nextLong() & 0xffffffffL,
              rnd.nextInt(16),
              awDelay = cycle + rnd.nextInt(4),
              wDelay = cycle + rnd.nextInt(4)
            ))
          if (rd.isEmpty && reads < 250) rd = Some(Rd(randomAddr(), cycle + rnd.nextInt(4)))
          val w = wr.getOrElse(Wr(0, 0L, 0, awSent = true, wSent = true, awDelay = 0, wDelay = 0))
          val awValid = !w.awSent && cycle >= w.awDelay
          val wValid = !w.wSent && cycle >= w.wDelay
          dut.io.axi.aw.valid.poke(awValid.B); dut.io.axi.aw.bits.addr.poke(w.addr.U); dut.io.axi.aw.bits.prot.poke(0.U)
          dut.io.axi.w.valid.poke(wValid.B); dut.io.axi.w.bits.data.poke(w.data.U);
          dut.io.axi.w.bits.strb.poke(w.strb.U)
          val arValid = rd.exists(r => !r.sent && cycle >= r.delay)
          rd.foreach(r => dut.io.axi.ar.bits.addr.poke(r.addr.U)); dut.io.axi.ar.bits.prot.poke(0.U)
          dut.io.axi.ar.valid.poke(arValid.B)
          val bReady = rnd.nextBoolean(); val rReady = rnd.nextBoolean()
          dut.io.axi.b.ready.poke(bReady.B); dut.io.axi.r.ready.poke(rReady.B)

          // Registers as the model has them now.
          for (i <- 0 until n) dut.io.value(i).expect(
            (regs(i).access match {
              case Access.Rw | Access.W1c => state(i)
              case _                      => 0L
            }).U,
            s"cycle $cycle: value of ${regs(i).name}"
          )
          val pulse = Array.tabulate(n)(i => dut.io.pulse(i).peek().litValue.toLong)

          // Responses.
          val bValid = dut.io.axi.b.valid.peek().litToBoolean
          if (bValid && bReady) {
            val done = lastWrite.getOrElse(fail(s"cycle $cycle: a B with no write in"))
            dut.io.axi.b.bits.expect(
              (if (mapped(done.addr & ~3)) AxiResp.Okay else AxiResp.SlvErr).U,
              f"cycle $cycle: B of 0x${done.addr}%x"
            )
            lastWrite = None; wr = None; writes += 1
          }
          if (rReady && dut.io.axi.r.valid.peek().litToBoolean) {
            val r = rd.filter(_.sent).getOrElse(fail(s"cycle $cycle: an R with no read in"))
            val (data, resp) = r.want.get
            dut.io.axi.r.bits.resp.expect(resp.U, f"cycle $cycle: R resp of 0x${r.addr}%x")
            dut.io.axi.r.bits.data.expect(data.U, f"cycle $cycle: R data of 0x${r.addr}%x")
            rd = None; reads += 1
          }
          // Requests taken this cycle; a read returns the registers as they are now.
          if (awValid && dut.io.axi.aw.ready.peek().litToBoolean) w.awSent = true
          if (wValid && dut.io.axi.w.ready.peek().litToBoolean) w.wSent = true
          if (w.awSent && w.wSent && lastWrite.isEmpty && wr.contains(w)) lastWrite = Some(w)
          if (arValid && dut.io.axi.ar.ready.peek().litToBoolean) {
            val r = rd.get
            val idx = regs.indexWhere(_.offset == (r.addr & ~3))
            r.want = Some(if (idx < 0) (0L, AxiResp.SlvErr)
            else {
              val reg = regs(idx)
              val v = reg.access match {
                case Access.Ro if reg.hiOf.isDefined => shadow(idx)
                case Access.Ro                       => reg.reset.getOrElse(hw(idx))
                case Access.Wo                       => 0L
                case _                               => state(idx)
              }
              (v, AxiResp.Okay)
            })
            // Reading a _LO latches its _HI's input in the same cycle.
            for ((reg, hi) <- regs.zipWithIndex if reg.hiOf.contains(regs.lift(idx).map(_.name).getOrElse("")))
              shadow(hi) = hw(hi)
            r.sent = true
          }
          prevW1c = state.clone(); prevHw = hw; prevPulse = pulse
          dut.clock.step(); cycle += 1

          // w1c: set by the hardware input of the cycle just ended.
          for (i <- 0 until n if regs(i).access == Access.W1c) state(i) = prevW1c(i) | prevHw(i)
          // B rising means the held write was done in the cycle just ended: apply it there.
          val bNow = dut.io.axi.b.valid.peek().litToBoolean
          // doWrite needs B idle, so a write was done in cycle c exactly when B was low in c and is high now.
          val wrote = bNow && !bValid
          if (wrote) {
            val done = lastWrite.getOrElse(fail(s"cycle $cycle: B rose with no write in"))
            val m = byteMask(done.strb)
            val idx = regs.indexWhere(_.offset == (done.addr & ~3))
            if (idx >= 0) regs(idx).access match {
              case Access.Rw  => state(idx) = (state(idx) & ~m) | (done.data & m)
              case Access.W1c => state(idx) = (prevW1c(idx) & ~(done.data & m)) | prevHw(idx)
              case _          =>
            }
            for (i <- 0 until n) {
              val want = if (i == idx && regs(i).access == Access.Wo) done.data & m else 0L
              assert(
                prevPulse(i) == want,
                s"cycle ${cycle - 1}: pulse of ${regs(i).name} is ${prevPulse(i)}, want $want"
              )
            }
          } else assert(prevPulse.forall(_ == 0L), s"cycle ${cycle - 1}: a pulse without a write")
        }
        assert(writes == 250 && reads == 250, s"after $cycle cycles: $writes writes and $reads reads answered")
      }
    }
}
