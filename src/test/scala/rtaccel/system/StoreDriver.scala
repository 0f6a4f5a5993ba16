package rtaccel.system

import chisel3._
import chiseltest._
import rtaccel.axi.{Axi4, Axi4Params}
import rtaccel.mem.MemPortParams
import rtaccel.sim.axi.SparseMemory

import scala.collection.mutable
import scala.util.Random

/** Drives an on-chip store (NodeStore, TriStore: anything with a StoreIO)
  * cycle by cycle from one thread: its fill from a SparseMemory (random
  * arready, in-order beats with gaps), then random reads by every client
  * with random ready, checked against the memory. Used by NodeStoreSpec and
  * TriStoreSpec; StoreFillSpec checks the fill's lines themselves.
  *
  * @param hits the store's hit rule: (address, base, stored bytes) => served on chip
  */
final class StoreDriver(
    io: StoreIO,
    clock: Clock,
    p: Axi4Params,
    recordBytes: Int,
    fillId: Int,
    mem: SparseMemory,
    rnd: Random,
    hits: (Long, Long, Long) => Boolean
) {
  private val B = p.beatBytes
  private val clients = io.req.size

  /** Loads `bytes` at `base`; returns the stored bytes the store reports. */
  def load(base: Long, bytes: Long): Long = {
    io.load.base.poke(base.U); io.load.bytes.poke(bytes.U); io.load.start.poke(true.B)
    for (c <- 0 until clients) { io.req(c).valid.poke(false.B); io.resp(c).ready.poke(true.B) }
    io.ar.ready.poke(false.B); io.r.valid.poke(false.B)
    clock.step(); io.load.start.poke(false.B)
    val bursts = mutable.Queue.empty[(Long, Int, Long)]
    var cycle = 0L
    while (!io.load.done.peek().litToBoolean && cycle < 20000) {
      for (c <- 0 until clients) io.hit(c).expect(false.B, s"fill cycle $cycle: client $c hits before the load is done")
      val arReady = rnd.nextInt(3) > 0
      io.ar.ready.poke(arReady.B)
      val beat = bursts.headOption.filter(_._3 <= cycle && rnd.nextInt(4) > 0)
      io.r.valid.poke(beat.isDefined.B)
      beat.foreach { case (addr, left, due) =>
        io.r.bits.id.poke(fillId.U); io.r.bits.resp.poke(Axi4.RespOkay.U)
        io.r.bits.data.poke(mem.readLE(addr, B).U); io.r.bits.last.poke((left == 1).B)
        if (left == 1) bursts.dequeue() else bursts(0) = (addr + B, left - 1, due)
      }
      if (arReady && io.ar.valid.peek().litToBoolean) {
        io.ar.bits.id.expect(fillId.U, "the fill's AXI ID")
        bursts.enqueue((
          io.ar.bits.addr.peek().litValue.toLong,
          io.ar.bits.len.peek().litValue.toInt + 1,
          cycle + 1 + rnd.nextInt(10)
        ))
      }
      clock.step(); cycle += 1
    }
    io.ar.ready.poke(false.B); io.r.valid.poke(false.B)
    assert(io.load.done.peek().litToBoolean && bursts.isEmpty, s"the load did not finish in $cycle cycles")
    clock.step(2) // the last line's write, and the registered limit
    io.error.expect(false.B, "error after the fill")
    io.load.storedBytes.peek().litValue.toLong
  }

  /** Every client asks for the record at `addr` every cycle and takes every answer, for `warm` cycles and then
    * `cycles` counted ones; returns the answers each client got in the counted cycles (each checked against the
    * memory). The ports' full rate: one answer per port per cycle, split evenly among the clients sharing them.
    * Only the clients in `asking` ask; the others get nothing.
    */
  def saturate(addr: Long, warm: Int, cycles: Int, asking: Set[Int] = (0 until clients).toSet): Seq[Int] = {
    val want = mem.readLE(addr, recordBytes)
    val got = Array.fill(clients)(0)
    for (c <- 0 until clients) {
      io.req(c).valid.poke(asking(c).B); io.req(c).bits.addr.poke(addr.U); io.req(c).bits.tag.poke(c.U)
      io.resp(c).ready.poke(true.B)
    }
    for (cycle <- 0 until warm + cycles) {
      for (c <- 0 until clients if io.resp(c).valid.peek().litToBoolean) {
        io.resp(c).bits.data.expect(want.U, s"saturated cycle $cycle: client $c record")
        io.resp(c).bits.tag.expect(c.U, s"saturated cycle $cycle: client $c tag")
        if (cycle >= warm) got(c) += 1
      }
      clock.step()
      io.error.expect(false.B, s"saturated cycle $cycle: error")
    }
    for (c <- 0 until clients) io.req(c).valid.poke(false.B)
    // drain (the triangle store's data stage and its answer queue's extra entry included)
    clock.step(TriStore.SharedLatency + NodeStore.OutDepth + TriStore.DataStages + 2)
    got.toSeq
  }

  /** `n` random reads per client of addresses the store holds, with random valid and ready; every one answered
    * once, in order per client, with the memory's record and its tag. Also checks `hit` on random probes.
    */
  def serve(base: Long, stored: Long, n: Int): Unit = {
    val tagBits = io.req(0).bits.tag.getWidth
    def randomHit(): Long = {
      var a = 0L
      do a = base + rnd.nextLong(stored + 64) / 16 * 16 while (!hits(a, base, stored))
      a
    }
    val offer = Array.fill[Option[(Long, Int)]](clients)(None)
    val want = Array.fill(clients)(mutable.Queue.empty[(Int, BigInt)])
    val sent = Array.fill(clients)(0)
    var got = 0
    var cycle = 0
    while (got < n * clients && cycle < 50 * n) {
      for (c <- 0 until clients) {
        // Probe: the hit rule on an address near the stored range, any alignment.
        val probe = base - 64 + rnd.nextLong(stored + 128)
        io.probe(c).poke(probe.U)
        io.hit(c).expect(
          hits(probe, base, stored).B,
          f"cycle $cycle: client $c probe 0x$probe%x (base 0x$base%x, stored $stored)"
        )
        if (offer(c).isEmpty && sent(c) < n && rnd.nextInt(3) > 0)
          offer(c) = Some((randomHit(), rnd.nextInt(1 << tagBits)))
        io.req(c).valid.poke(offer(c).isDefined.B)
        offer(c).foreach { case (a, t) => io.req(c).bits.addr.poke(a.U); io.req(c).bits.tag.poke(t.U) }
      }
      val readies = Seq.fill(clients)(rnd.nextInt(3) > 0)
      for (c <- 0 until clients) {
        io.resp(c).ready.poke(readies(c).B)
        if (readies(c) && io.resp(c).valid.peek().litToBoolean) {
          assert(want(c).nonEmpty, s"cycle $cycle: client $c got a response it did not ask for")
          val (tag, data) = want(c).dequeue()
          io.resp(c).bits.tag.expect(tag.U, s"cycle $cycle: client $c tag")
          io.resp(c).bits.data.expect(data.U, s"cycle $cycle: client $c record")
          got += 1
        }
        if (offer(c).isDefined && io.req(c).ready.peek().litToBoolean) {
          val (a, t) = offer(c).get
          want(c).enqueue((t, mem.readLE(a, recordBytes)))
          offer(c) = None; sent(c) += 1
        }
      }
      clock.step(); cycle += 1
      io.error.expect(false.B, s"cycle $cycle: error")
    }
    for (c <- 0 until clients) io.req(c).valid.poke(false.B)
    assert(
      got == n * clients,
      s"after $cycle cycles: $got of ${n * clients} reads answered (owed ${want.map(_.size).mkString(", ")})"
    )
  }
}

object StoreDriver {

  /** Checks `saturate`'s answers against the ports' full rate: the clients sharing a copy's ports get one answer per
    * port per cycle between them, each an even share (within `slack`: the two round-robin picks rotate unevenly
    * for a few cycles); a client that does not ask leaves its share to the others.
    */
  def checkRate(groups: Seq[StorePort.Group], got: Seq[Int], cycles: Int, asking: Int => Boolean): Unit =
    for (g <- groups) {
      val askers = g.clients.filter(asking)
      val total = askers.map(got).sum
      val full = cycles * g.ports.size.min(askers.size)
      assert(
        math.abs(total - full) <= g.ports.size,
        s"clients ${g.clients.mkString(", ")} on ${g.ports.size} port(s): $total answers in $cycles saturated " +
          s"cycles, not $full"
      )
      for (c <- g.clients)
        if (!asking(c)) assert(got(c) == 0, s"client $c did not ask but got ${got(c)} answers")
        else
          assert(
            math.abs(got(c) - full / askers.size) <= 2,
            s"client $c of ${askers.size} asking on ${g.ports.size} port(s): ${got(c)} answers in $cycles saturated " +
              s"cycles, not about ${full / askers.size}"
          )
    }

  /** What NodeStoreSpec and TriStoreSpec drive a store with. */
  final case class Bench(p: Axi4Params, port: MemPortParams, mem: SparseMemory)

  /** A 32-bit AXI4 of `dataBits`-bit beats (6-bit IDs), a client port of `recordBytes`-byte records (4-bit tags),
    * and 64 KiB of random bytes from `rnd` at 0x10000, the window both specs load from. */
  def bench(dataBits: Int, recordBytes: Int, rnd: Random): Bench = {
    val mem = new SparseMemory
    mem.write(0x10000, Array.fill(0x10000)(rnd.nextInt(256).toByte))
    Bench(
      Axi4Params(addrBits = 32, dataBits = dataBits, idBits = 6),
      MemPortParams(addrBits = 32, tagBits = 4, recordBytes = recordBytes),
      mem
    )
  }
}
