package rtaccel.sim.mem

import chisel3._
import chiseltest._

import scala.util.Random
import rtaccel.mem.MemPort

/** Connects a DUT's memory port to a MemorySystemModel, one cycle at a time,
  * in a single-threaded test loop (no chiseltest `fork`).
  *
  * Call `drive()` after poking the DUT's other inputs and before stepping the
  * clock, then `tick()` after the step.
  */
final class MemPortHarness(port: MemPort, model: MemorySystemModel, refuse: Double = 0.0, rnd: Random = new Random(0)) {
  val driver = new MemPortDriver(model, refuse, rnd)
  def lastRequest: Option[(Long, Int)] = driver.lastRequest

  // What is on the DUT's inputs now: chiseltest calls cost microseconds, so
  // unchanged values are not poked again.
  private var readyNow: Option[Boolean] = None
  private var respNow: Option[Option[(Int, BigInt)]] = None

  def drive(): Unit = {
    val reqValid = port.req.valid.peek().litToBoolean
    val addr = if (reqValid) port.req.bits.addr.peek().litValue.toLong else 0L
    val ready = driver.ready(reqValid, addr)
    if (!readyNow.contains(ready)) { port.req.ready.poke(ready.B); readyNow = Some(ready) }
    val resp = driver.response
    if (!respNow.contains(resp)) {
      resp match {
        case Some((tag, data)) =>
          port.resp.valid.poke(true.B)
          port.resp.bits.tag.poke(tag.U)
          port.resp.bits.data.poke(data.U)
        case None => port.resp.valid.poke(false.B)
      }
      respNow = Some(resp)
    }
    val respFired = resp.isDefined && port.resp.ready.peek().litToBoolean
    driver.commit(reqValid, ready, addr, port.req.bits.tag.peek().litValue.toInt, respFired)
  }

  def tick(): Unit = driver.tick()
}
