package rtaccel.sim.axi

import chisel3._
import chiseltest._
import rtaccel.axi.{Axi4Addr, Axi4Master}

/** Connects a DUT's Axi4Master bundle to an AxiMemoryModel in a
  * single-threaded chiseltest loop (no `fork`):
  * {{{
  *   val mem = new AxiMemoryHarness(dut.io.axi, new AxiMemoryModel(AxiMemoryParams().harsh(seed)))
  *   mem.model.mem.write(base, imageBytes)
  *   while (...) { /* poke other inputs */; mem.drive(); /* peek outputs */; dut.clock.step(); mem.tick() }
  * }}}
  * `drive()` pokes the slave's outputs, peeks the master's and commits the
  * cycle's handshakes (a protocol violation throws AxiProtocolError).
  * For a top with flat m_axi_* ports, do the same with `model.slave` and
  * `model.commit` on those ports.
  */
final class AxiMemoryHarness(axi: Axi4Master, val model: AxiMemoryModel) {
  // chiseltest calls cost microseconds: poke only what changed.
  private var last: Option[AxiSlaveSignals] = None

  private def addr(a: Axi4Addr): AxiAddrBeat = AxiAddrBeat(
    a.id.peek().litValue.toInt,
    a.addr.peek().litValue.toLong,
    a.len.peek().litValue.toInt,
    a.size.peek().litValue.toInt,
    a.burst.peek().litValue.toInt
  )

  def drive(): Unit = {
    val s = model.slave
    if (!last.contains(s)) {
      axi.ar.ready.poke(s.arReady.B)
      axi.aw.ready.poke(s.awReady.B)
      axi.w.ready.poke(s.wReady.B)
      axi.r.valid.poke(s.r.isDefined.B)
      s.r.foreach { r =>
        axi.r.bits.id.poke(r.id.U); axi.r.bits.data.poke(r.data.U); axi.r.bits.resp.poke(r.resp.U);
        axi.r.bits.last.poke(r.last.B)
      }
      axi.b.valid.poke(s.b.isDefined.B)
      s.b.foreach { b => axi.b.bits.id.poke(b.id.U); axi.b.bits.resp.poke(b.resp.U) }
      last = Some(s)
    }
    val m = AxiMasterSignals(
      ar = Option.when(axi.ar.valid.peek().litToBoolean)(addr(axi.ar.bits)),
      aw = Option.when(axi.aw.valid.peek().litToBoolean)(addr(axi.aw.bits)),
      w = Option.when(axi.w.valid.peek().litToBoolean)(
        AxiWBeat(axi.w.bits.data.peek().litValue, axi.w.bits.strb.peek().litValue, axi.w.bits.last.peek().litToBoolean)
      ),
      rReady = s.r.isDefined && axi.r.ready.peek().litToBoolean,
      bReady = s.b.isDefined && axi.b.ready.peek().litToBoolean
    )
    model.commit(m)
  }

  def tick(): Unit = model.tick()
}
