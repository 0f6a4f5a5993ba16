package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.axi.{Axi4, Axi4Params}
import rtaccel.sim.Backends
import rtaccel.sim.axi.SparseMemory
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** StoreFill alone, against a Scala AXI slave over a SparseMemory of random
  * bytes: random arready, each burst answered after a random delay with gaps
  * between beats (R has no ready: the fill always takes). For loads shorter
  * and longer than the capacity, the scoreboard is the store's lines: each
  * line below the stored size is written exactly once, with the DRAM bytes at
  * base + line * beat, and nothing else; bursts use the fill ID, stay inside
  * 4 KB, are at most `FillBurstBeats` long and at most `FillBursts` are
  * outstanding; `done`, `storedBytes`, `ready` and `limit` follow.
  */
class StoreFillSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "StoreFill"

  private val capacity = 8192
  private val fillId = 5

  // 1024-bit beats with a base at 64 mod 128 take the realigning path (one extra beat).
  for ((dataBits, wordBeats) <- Seq((512, 1), (1024, 1), (512, 2))) {
    it should s"write every line of a load once, with DRAM's bytes, under random back-pressure ($dataBits-bit beats, ${wordBeats}-beat words)" in
      Seeded(s"StoreFill.$dataBits.$wordBeats") { rnd =>
        val p = Axi4Params(addrBits = 32, dataBits = dataBits, idBits = 6)
        val B = p.beatBytes
        val wordBytes = B * wordBeats
        val mem = new SparseMemory
        mem.write(0x10000, Array.fill(0x10000)(rnd.nextInt(256).toByte))
        test(new StoreFill(p, capacity, wordBytes, fillId)).withAnnotations(Backends.treadle) { dut =>
          for ((base, bytes) <- Seq((0x10040L, 3000L), (0x11000L, 100000L), (0x12fc0L, 1L), (0x13000L, 0x1840L))) {
            dut.io.load.base.poke(base.U); dut.io.load.bytes.poke(bytes.U)
            dut.io.load.start.poke(true.B)
            dut.io.ar.ready.poke(false.B); dut.io.r.valid.poke(false.B)
            dut.io.ready.expect(false.B, "not ready in the cycle a load starts")
            dut.clock.step(); dut.io.load.start.poke(false.B)
            val words = ((bytes + wordBytes - 1) / wordBytes).min(capacity / wordBytes)
            val lines = (words * wordBeats).toInt
            val written = mutable.Map.empty[Int, BigInt]
            val bursts = mutable.Queue.empty[(Long, Int, Long)] // (address, beats left, cycle due)
            var outstanding = 0
            var cycle = 0L
            while (dut.io.load.busy.peek().litToBoolean && cycle < 20000) {
              dut.io.load.done.expect(false.B); dut.io.ready.expect(false.B)
              val arReady = rnd.nextInt(3) > 0
              dut.io.ar.ready.poke(arReady.B)
              val beat = bursts.headOption.filter(_._3 <= cycle && rnd.nextInt(4) > 0)
              dut.io.r.valid.poke(beat.isDefined.B)
              beat.foreach { case (addr, left, due) =>
                dut.io.r.bits.id.poke(fillId.U); dut.io.r.bits.resp.poke(Axi4.RespOkay.U)
                dut.io.r.bits.data.poke(mem.readLE(addr, B).U); dut.io.r.bits.last.poke((left == 1).B)
                if (left == 1) { bursts.dequeue(); outstanding -= 1 }
                else bursts(0) = (addr + B, left - 1, due)
              }
              if (dut.io.write.valid.peek().litToBoolean) {
                val line = dut.io.write.bits.line.peek().litValue.toInt
                assert(
                  line < lines && !written.contains(line),
                  s"cycle $cycle: line $line written twice or beyond the $lines lines"
                )
                written(line) = dut.io.write.bits.data.peek().litValue
              }
              if (arReady && dut.io.ar.valid.peek().litToBoolean) {
                val a = dut.io.ar.bits
                val addr = a.addr.peek().litValue.toLong; val beats = a.len.peek().litValue.toInt + 1
                a.id.expect(fillId.U, "fill ID")
                assert(beats <= StoreFill.FillBurstBeats, s"cycle $cycle: a burst of $beats beats")
                assert(
                  addr / 4096 == (addr + beats * B - 1) / 4096,
                  f"cycle $cycle: burst at 0x$addr%x of $beats beats crosses 4 KB"
                )
                outstanding += 1
                assert(outstanding <= StoreFill.FillBursts, s"cycle $cycle: $outstanding bursts outstanding")
                bursts.enqueue((addr, beats, cycle + 1 + rnd.nextInt(10)))
              }
              dut.clock.step(); cycle += 1
            }
            // The last beat's write leaves a cycle after `busy` falls.
            dut.io.ar.ready.poke(false.B); dut.io.r.valid.poke(false.B)
            for (_ <- 0 until 3) {
              if (dut.io.write.valid.peek().litToBoolean) {
                val line = dut.io.write.bits.line.peek().litValue.toInt
                assert(line < lines && !written.contains(line), s"line $line written twice or beyond the $lines lines")
                written(line) = dut.io.write.bits.data.peek().litValue
              }
              dut.io.ar.valid.expect(false.B, "an AR after the fill")
              dut.clock.step()
            }
            assert(bursts.isEmpty, "beats asked for but never taken")
            assert(written.size == lines, f"load of $bytes bytes at 0x$base%x: ${written.size} of $lines lines written")
            for (j <- 0 until lines)
              assert(written(j) == mem.readLE(base + j.toLong * B, B), f"line $j of the load at 0x$base%x")
            dut.io.load.done.expect(true.B); dut.io.ready.expect(true.B); dut.io.error.expect(false.B)
            dut.io.load.storedBytes.expect((lines * B).U)
            dut.io.base.expect(base.U); dut.io.limit.expect((base + lines * B).U)
          }
        }
      }
  }
}
