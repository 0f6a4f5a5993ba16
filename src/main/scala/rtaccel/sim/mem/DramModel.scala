package rtaccel.sim.mem

import scala.collection.mutable

/** A DRAM's data channel, shared by every port that issues to it. Each
  * transfer waits its latency (drawn by the issuing port), then its bytes,
  * charged as whole bursts (`DramModel.burstCharge`), cross one channel of
  * `bytesPerCycle` that all transfers share.
  *
  * Timing: a transfer issued in cycle c with latency L that fits one cycle of
  * channel completes in the tick of cycle c + L - 1 if the channel is free,
  * so its requester sees it from cycle c + L on; each further cycle of channel
  * it needs, or spends waiting for another transfer, adds one.
  *
  * Arbitration: the transfer that became ready first (ties: issued first).
  * A client that answers in order has only its oldest pending transfer
  * eligible (head-of-line blocking, as behind one in-order queue).
  *
  * Sharing: every port issues its requests of a cycle before any port ticks;
  * the first `tick(now)` of a cycle moves that cycle's data for all of them,
  * later ones in the same cycle do nothing.
  *
  * Bandwidth is kept in thousandths of a byte, so a clock that does not
  * divide the peak (e.g. 51.2 B/cycle at 250 MHz) accumulates no rounding.
  */
final class DramModel(val bytesPerCycle: Double, val burstBytes: Int) {
  require(bytesPerCycle > 0, s"DramModel: bytesPerCycle must be > 0, got $bytesPerCycle")
  require(burstBytes >= 1, s"DramModel: burstBytes must be >= 1, got $burstBytes")
  private val milliPerCycle: Long = math.round(bytesPerCycle * 1000)

  private final class Transfer(val client: DramModel.Client, val id: Long, val readyAt: Long, var milliLeft: Long)
  private val pending = mutable.ArrayBuffer.empty[Transfer] // issue order
  private var lastTick = -1L
  private var bytes = 0L
  private var busyCycles = 0L

  def inFlight: Int = pending.size

  /** Starts a transfer of the `n`-byte record at `addr`; returns the bytes charged. */
  def issue(client: DramModel.Client, id: Long, addr: Long, n: Int, latency: Int, now: Long): Int = {
    require(latency >= 1, s"DramModel: latency must be >= 1 cycle, got $latency")
    require(now > lastTick, s"DramModel: issue in cycle $now after the channel moved cycle $lastTick's data")
    val charged = DramModel.burstCharge(addr, n, burstBytes)
    pending += new Transfer(client, id, now + latency - 1, charged * 1000L)
    bytes += charged
    charged
  }

  /** Moves cycle `now`'s data and tells each client which of its transfers completed. */
  def tick(now: Long): Unit = if (now != lastTick) {
    require(
      now == lastTick + 1,
      s"DramModel: ticked for cycle $now after cycle $lastTick (a sharing port missed a tick)"
    )
    lastTick = now
    var budget = milliPerCycle
    var moved = false
    var t = next(now)
    while (budget > 0 && t.isDefined) {
      val x = t.get
      val n = math.min(budget, x.milliLeft)
      x.milliLeft -= n
      budget -= n
      moved = true
      if (x.milliLeft == 0) {
        pending -= x
        x.client.completed(x.id)
        t = next(now)
      }
    }
    if (moved) busyCycles += 1
  }

  private def next(now: Long): Option[Transfer] = {
    var best: Transfer = null
    var headsSeen = List.empty[DramModel.Client] // in-order clients whose oldest transfer is behind us
    for (t <- pending) {
      val eligible = !(t.client.inOrder && headsSeen.contains(t.client))
      if (eligible && t.readyAt <= now && (best == null || t.readyAt < best.readyAt)) best = t
      if (t.client.inOrder && !headsSeen.contains(t.client)) headsSeen ::= t.client
    }
    Option(best)
  }

  def stats(cycles: Long): DramStats = DramStats(cycles, bytes, bytesPerCycle, burstBytes, busyCycles)
}

object DramModel {

  /** A requester of transfers: told when each of its transfers has crossed the channel. */
  trait Client {
    def inOrder: Boolean
    def completed(id: Long): Unit
  }

  /** Bytes a DRAM moves to read `n` bytes at `addr`: every `burst`-aligned
    * burst the range touches, in full. A 48-byte read at 48 touches [0, 64)
    * and [64, 128): 128 bytes.
    */
  def burstCharge(addr: Long, n: Int, burst: Int): Int = {
    require(n >= 1 && addr >= 0, s"burstCharge: need n >= 1 and addr >= 0, got n=$n addr=$addr")
    ((addr + n - 1) / burst - addr / burst + 1).toInt * burst
  }
}
