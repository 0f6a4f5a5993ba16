package rtaccel.sim.mem

import scala.util.Random

/** The per-cycle decisions of a memory port, apart from how they reach the
  * DUT (pokes on a MemPort, or a packed simulation wrapper): whether to accept
  * the DUT's request, which response to offer, and the bookkeeping after.
  * `refuse` adds seeded random back-pressure on top of the model's own limits.
  */
final class MemPortDriver(val model: MemorySystemModel, refuse: Double, rnd: Random) {
  var requestsAccepted = 0L
  var responsesDelivered = 0L

  /** The request accepted in the last cycle, as (address, tag). */
  var lastRequest: Option[(Long, Int)] = None

  /** Accept the DUT's request this cycle? Call once per cycle. */
  def ready(reqValid: Boolean, addr: Long): Boolean =
    reqValid && model.reqReady(addr) && !(refuse > 0 && rnd.nextDouble() < refuse)

  def response: Option[(Int, BigInt)] = model.response

  /** Records what fired this cycle; call before the clock edge, then `tick()` after it. */
  def commit(reqValid: Boolean, reqReady: Boolean, addr: Long, tag: => Int, respFired: Boolean): Unit = {
    if (respFired) { model.responseTaken(); responsesDelivered += 1 }
    lastRequest = None
    if (reqValid && reqReady) {
      model.accept(addr, tag)
      lastRequest = Some((addr, tag))
      requestsAccepted += 1
    } else if (reqValid) model.stalled()
  }

  def tick(): Unit = model.tick()
}
