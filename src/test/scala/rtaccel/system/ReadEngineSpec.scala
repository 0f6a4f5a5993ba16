package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.{Axi4, Axi4Params}
import rtaccel.sim.Backends
import rtaccel.sim.axi.SparseMemory
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** ReadEngine alone, against a Scala AXI slave over a SparseMemory of random
  * bytes. Three clients ask for records of 32, 48 and 100 bytes at any byte
  * alignment (many near a 4 KB boundary), with seeded random valid (held until
  * taken), random arready and random ready per client; the slave answers each
  * burst after a random delay, interleaving IDs at random (beats of one ID in
  * order). The scoreboard is every request: its record comes back exactly
  * once, to its own client, with its tag and bytes; every burst is beat-aligned,
  * stays inside its 4 KB page and uses an ID below `slots`; `error` stays low.
  */
class ReadEngineSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "ReadEngine"

  private val recordBytes = Seq(32, 48, 100)

  for (dataBits <- Seq(512, 1024)) {
    it should s"return every record once, to its client, under random back-pressure on AR, R and every client ($dataBits-bit beats)" in
      Seeded(s"ReadEngine.$dataBits") { rnd =>
        val p = Axi4Params(addrBits = 32, dataBits = dataBits, idBits = 6)
        val B = p.beatBytes
        val slots = 6
        val tagBits = 4
        val span = 1 << 16
        val mem = new SparseMemory
        mem.write(0, Array.fill(span + 4096)(rnd.nextInt(256).toByte))
        test(new ReadEngine(p, recordBytes, tagBits, slots)).withAnnotations(Backends.verilator) { dut =>
          val requests = 150
          var issued = 0
          var offer: Option[(Long, Int, Int)] = None // (addr, client, tag)
          val want = Array.fill(recordBytes.size)(mutable.ArrayBuffer.empty[(Int, BigInt)])
          var answered = 0
          // The slave: bursts per ID in AR order, each (address, beats left, cycle due).
          val bursts = mutable.Map.empty[Int, mutable.Queue[(Long, Int, Long)]]
          var cycle = 0L
          while (answered < requests && cycle < 40L * requests) {
            if (offer.isEmpty && issued < requests && rnd.nextInt(3) > 0) {
              val client = rnd.nextInt(recordBytes.size)
              val addr = if (rnd.nextBoolean()) (4096L * (1 + rnd.nextInt(span / 4096 - 1)) - rnd.nextInt(2 * B))
              else rnd.nextInt(span).toLong
              offer = Some((addr, client, rnd.nextInt(1 << tagBits)))
            }
            dut.io.req.valid.poke(offer.isDefined.B)
            offer.foreach { case (a, c, t) =>
              dut.io.req.bits.addr.poke(a.U); dut.io.req.bits.client.poke(c.U); dut.io.req.bits.tag.poke(t.U)
            }
            val arReady = rnd.nextInt(3) > 0
            dut.io.ar.ready.poke(arReady.B)
            // R: one beat of a random ID whose head burst is due, on a coin toss.
            val due = bursts.collect { case (id, q) if q.nonEmpty && q.head._3 <= cycle => id }.toSeq.sorted
            val rId = if (due.nonEmpty && rnd.nextInt(4) > 0) Some(due(rnd.nextInt(due.size))) else None
            dut.io.r.valid.poke(rId.isDefined.B)
            rId.foreach { id =>
              val q = bursts(id)
              val (addr, left, d) = q.head
              dut.io.r.bits.id.poke(id.U)
              dut.io.r.bits.data.poke(mem.readLE(addr, B).U)
              dut.io.r.bits.resp.poke(Axi4.RespOkay.U)
              dut.io.r.bits.last.poke((left == 1).B)
              if (left == 1) q.dequeue() else q(0) = (addr + B, left - 1, d)
            }
            val readies = recordBytes.indices.map(_ => rnd.nextInt(3) > 0)
            for (c <- recordBytes.indices) dut.io.resp(c).ready.poke(readies(c).B)

            for (c <- recordBytes.indices if readies(c) && dut.io.resp(c).valid.peek().litToBoolean) {
              val tag = dut.io.resp(c).bits.tag.peek().litValue.toInt
              val data = dut.io.resp(c).bits.data.peek().litValue
              val i = want(c).indexOf((tag, data))
              assert(i >= 0, s"cycle $cycle: client $c got tag $tag with a record no request of it is owed")
              want(c).remove(i); answered += 1
            }
            if (offer.isDefined && dut.io.req.ready.peek().litToBoolean) {
              val (a, c, t) = offer.get
              want(c) += ((t, mem.readLE(a, recordBytes(c))))
              offer = None; issued += 1
            }
            if (arReady && dut.io.ar.valid.peek().litToBoolean) {
              val a = dut.io.ar.bits
              val id = a.id.peek().litValue.toInt
              val addr = a.addr.peek().litValue.toLong
              val beats = a.len.peek().litValue.toInt + 1
              assert(id < slots, s"cycle $cycle: AR ID $id beyond $slots slots")
              assert(addr % B == 0, f"cycle $cycle: AR address 0x$addr%x not beat-aligned")
              assert(
                addr / 4096 == (addr + beats * B - 1) / 4096,
                f"cycle $cycle: burst at 0x$addr%x of $beats beats crosses 4 KB"
              )
              a.size.expect(p.fullSize.U); a.burst.expect(Axi4.BurstIncr.U)
              bursts.getOrElseUpdate(id, mutable.Queue.empty) += ((addr, beats, cycle + 1 + rnd.nextInt(12)))
            }
            dut.clock.step(); cycle += 1
            dut.io.error.expect(false.B, s"cycle $cycle: error")
          }
          assert(
            answered == requests,
            s"after $cycle cycles: $answered of $requests records answered; owed ${want.map(_.size).mkString(", ")}"
          )
          assert(bursts.values.forall(_.isEmpty), "bursts never answered")
          dut.clock.step()
          dut.io.idle.expect(true.B, "idle after the last record")
        }
      }
  }
}
