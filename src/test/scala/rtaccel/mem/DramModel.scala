package rtaccel.mem

import scala.collection.mutable
import scala.util.Random

/** DRAM behind one port: every transfer waits its latency, then its bytes
  * cross a return channel of `bytesPerCycle`. In-order mode completes
  * transfers in issue order (head-of-line blocking); otherwise the channel
  * serves whichever ready transfer became ready first.
  *
  * Timing: a transfer issued in cycle c, with latency L and no contention for
  * the channel, completes in the tick of cycle c + L - 1, so its requester
  * sees it from cycle c + L on.
  */
final class DramModel(latency: Latency, bytesPerCycle: Int, inOrder: Boolean, rnd: Random) {
  private final class Transfer(val id: Long, val readyAt: Long, var remaining: Int)
  private val pending = mutable.ArrayBuffer.empty[Transfer] // issue order
  var bytesMoved: Long = 0

  def inFlight: Int = pending.size

  def issue(id: Long, bytes: Int, now: Long): Unit = {
    val l = latency match {
      case Latency.Fixed(c)       => c
      case Latency.Uniform(lo, hi) => lo + rnd.nextInt(hi - lo + 1)
    }
    pending += new Transfer(id, now + l - 1, bytes)
    bytesMoved += bytes
  }

  /** Moves this cycle's bytes; returns the transfers that completed. */
  def tick(now: Long): Seq[Long] = {
    var budget = bytesPerCycle
    val completed = mutable.ArrayBuffer.empty[Long]
    var progress = true
    while (budget > 0 && progress) {
      val next =
        if (inOrder) pending.headOption.filter(_.readyAt <= now)
        else pending.iterator.filter(_.readyAt <= now).minByOption(_.readyAt)
      next match {
        case Some(t) =>
          val n = math.min(budget, t.remaining)
          t.remaining -= n
          budget -= n
          if (t.remaining == 0) { pending -= t; completed += t.id }
        case None => progress = false
      }
    }
    completed.toSeq
  }
}
