package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.{Axi4, Axi4Params}
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** WriteEngine alone: seeded random valid on `write`, random ready on AW and W,
  * and a Scala AXI slave answering each (AW, W) pair with a B after a random
  * delay (a few SLVERRs among them). The scoreboard is the list of lines
  * offered, each with one or both of its 32-byte records: each line leaves
  * exactly once, in order, as one single-beat burst at its beat address with
  * its 64 bytes in its place and the strobes of its records only;
  * `writesDone` counts the records of the Bs come, each two cycles after its
  * B, and `error` rises with the first SLVERR.
  */
class WriteEngineSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "WriteEngine"

  for (dataBits <- Seq(512, 1024)) {
    it should s"write every line once, in order, under random back-pressure on AW, W and write ($dataBits-bit beats)" in
      Seeded(s"WriteEngine.$dataBits") { rnd =>
        val p = Axi4Params(addrBits = 32, dataBits = dataBits, idBits = 6)
        val beat = p.beatBytes
        val L = WriteRecord.Bytes
        val R = WriteRecord.RecordBytes
        test(new WriteEngine(p)).withAnnotations(Backends.treadle) { dut =>
          val records = 300
          val offered = Seq.fill(records)((rnd.nextInt(1 << 20).toLong * L, BigInt(8 * L, rnd), 1 + rnd.nextInt(3)))
          def recordsOf(n: Int) = Integer.bitCount(offered(n)._3)
          var next = 0
          val awWant = mutable.Queue.empty[(Long, BigInt, Int)]
          val wWant = mutable.Queue.empty[(Long, BigInt, Int)]
          var awSeen, wSeen = 0
          val bQueue = mutable.Queue.empty[(Long, Int)] // (cycle due, resp)
          var bDone, recordsDone, recordsLate = 0
          var errorWant = false
          val slvErrAt = Set(records / 3, 2 * records / 3)
          var offering = false
          var cycle = 0L
          while ((bDone < records) && cycle < 20000) {
            // Master side: offer the next record on a coin toss; hold it until taken.
            offering = next < records && (offering || rnd.nextInt(4) > 0)
            dut.io.write.valid.poke(offering.B)
            if (next < records) {
              dut.io.write.bits.addr.poke(offered(next)._1.U); dut.io.write.bits.data.poke(offered(next)._2.U)
              dut.io.write.bits.halves.poke(offered(next)._3.U)
            }
            val awReady = rnd.nextInt(3) > 0; val wReady = rnd.nextInt(3) > 0
            dut.io.aw.ready.poke(awReady.B); dut.io.w.ready.poke(wReady.B)
            // B: the oldest due response, if any.
            val bValid = bQueue.headOption.exists(_._1 <= cycle)
            dut.io.b.valid.poke(bValid.B)
            dut.io.b.bits.id.poke(0.U)
            dut.io.b.bits.resp.poke(bQueue.headOption.map(_._2).getOrElse(0).U)
            dut.io.b.ready.expect(true.B, "bready is always high")

            if (offering && dut.io.write.ready.peek().litToBoolean) {
              awWant.enqueue(offered(next)); wWant.enqueue(offered(next)); next += 1; offering = false
            }
            if (awReady && dut.io.aw.valid.peek().litToBoolean) {
              assert(awWant.nonEmpty, s"cycle $cycle: an AW with no record offered")
              val (addr, _, _) = awWant.dequeue()
              val a = dut.io.aw.bits
              a.addr.expect((addr / beat * beat).U, s"cycle $cycle: AW $awSeen address")
              a.id.expect(0.U); a.len.expect(0.U); a.size.expect(p.fullSize.U); a.burst.expect(Axi4.BurstIncr.U)
              awSeen += 1
            }
            if (wReady && dut.io.w.valid.peek().litToBoolean) {
              assert(wWant.nonEmpty, s"cycle $cycle: a W beat with no record offered")
              val (addr, data, halves) = wWant.dequeue()
              val lane = (addr % beat).toInt
              val w = dut.io.w.bits
              val gotData = w.data.peek().litValue
              val strb = (0 until 2).filter(h => (halves >> h & 1) == 1).map(h =>
                ((BigInt(1) << R) - 1) << (lane + R * h)
              ).reduce(_ | _)
              for (h <- 0 until 2 if (halves >> h & 1) == 1) {
                val field = (v: BigInt, at: Int) => (v >> (8 * at)) & ((BigInt(1) << (8 * R)) - 1)
                assert(field(gotData, lane + R * h) == field(data, R * h), s"cycle $cycle: W $wSeen data, record $h")
              }
              w.strb.expect(strb.U, s"cycle $cycle: W $wSeen strobes")
              w.last.expect(true.B)
              wSeen += 1
            }
            // The slave answers a pair once both halves are in.
            while (bQueue.size + bDone < awSeen.min(wSeen)) {
              val n = bQueue.size + bDone
              bQueue.enqueue((cycle + 1 + rnd.nextInt(8), if (slvErrAt(n)) 2 else Axi4.RespOkay))
            }
            dut.clock.step(); cycle += 1
            // A B's records are added a cycle after it (the add is registered): the B before last counts now.
            recordsDone += recordsLate; recordsLate = 0
            if (bValid) {
              val resp = bQueue.dequeue()._2; errorWant = errorWant || resp != Axi4.RespOkay;
              recordsLate = recordsOf(bDone); bDone += 1
            }
            dut.io.writesDone.expect(recordsDone.U, s"cycle $cycle: writesDone (records of the Bs come)")
            dut.io.error.expect(errorWant.B, s"cycle $cycle: error")
          }
          assert(
            bDone == records && awSeen == records && wSeen == records,
            s"after $cycle cycles: $awSeen AWs, $wSeen Ws, $bDone Bs of $records records"
          )
          dut.io.aw.valid.expect(false.B, "an AW left over")
          dut.io.w.valid.expect(false.B, "a W left over")
        }
      }
  }
}
