package rtaccel.mem

import chisel3._
import chiseltest._

import scala.util.Random

/** Connects a DUT's memory port to a MemorySystemModel, one cycle at a time,
  * in a single-threaded test loop (no chiseltest `fork`).
  *
  * Call `drive()` after poking the DUT's other inputs and before stepping the
  * clock, then `tick()` after the step. `refuse` adds seeded random
  * back-pressure on the request channel on top of the model's own limits.
  */
final class MemPortHarness(port: MemPort, val model: MemorySystemModel, refuse: Double = 0.0, rnd: Random = new Random(0)) {
  var requestsAccepted = 0L
  var responsesDelivered = 0L
  /** The request accepted in the last `drive()`, as (address, tag). */
  var lastRequest: Option[(Long, Int)] = None

  def drive(): Unit = {
    val reqValid = port.req.valid.peek().litToBoolean
    val addr     = port.req.bits.addr.peek().litValue.toLong
    val ready    = model.reqReady(addr) && !(refuse > 0 && rnd.nextDouble() < refuse)
    port.req.ready.poke(ready.B)
    model.response match {
      case Some((tag, data)) =>
        port.resp.valid.poke(true.B)
        port.resp.bits.tag.poke(tag.U)
        port.resp.bits.data.poke(data.U)
        if (port.resp.ready.peek().litToBoolean) { model.responseTaken(); responsesDelivered += 1 }
      case None =>
        port.resp.valid.poke(false.B)
    }
    lastRequest = None
    if (reqValid && ready) {
      val tag = port.req.bits.tag.peek().litValue.toInt
      model.accept(addr, tag)
      lastRequest = Some((addr, tag))
      requestsAccepted += 1
    } else if (reqValid) model.stalled()
  }

  def tick(): Unit = model.tick()
}
