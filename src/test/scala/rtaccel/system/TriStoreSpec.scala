package rtaccel.system

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** TriStore alone (StoreDriver): filled from a SparseMemory of random bytes
  * under random arready and R gaps, then read by three or four clients with
  * random valid and ready (one copy of the banks, its two ports shared by
  * all clients, and two copies, a port each) at every 16-byte offset,
  * records straddling two lines
  * (banks) included: every read answered once, in order per client, with the
  * DRAM record and its tag; `hit` follows the rule (loaded, 16-byte aligned
  * relative to base, the whole record below base + storedBytes) on random
  * probes; saturated, the ports answer once a cycle each, shared evenly
  * among the clients that ask.
  */
class TriStoreSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "TriStore"

  private val rec = 48
  private def hits(a: Long, base: Long, stored: Long): Boolean =
    a >= base && a + rec <= base + stored && (a - base) % TriStore.Grain == 0

  for ((dataBits, copies, clients) <- Seq((1024, 1, 3), (512, 2, 3), (512, 1, 4))) {
    it should s"serve every read of a loaded store once, with DRAM's triangle ($dataBits-bit beats, $copies " +
      s"${if (copies == 1) "copy" else "copies"} for $clients clients)" in
      Seeded(s"TriStore.$dataBits.$copies.$clients") { rnd =>
        val StoreDriver.Bench(p, port, mem) = StoreDriver.bench(dataBits, rec, rnd)
        test(
          new TriStore(p, port, clients = clients, capacityBytes = 4096, fillId = 3, copies = copies)
        ).withAnnotations(
          Backends.treadle
        ) {
          dut =>
            val drv = new StoreDriver(dut.io, dut.clock, p, rec, 3, mem, rnd, hits)
            for ((base, bytes) <- Seq((0x10040L, 1000L), (0x14000L, 100000L))) {
              val stored = drv.load(base, bytes)
              val lines = (bytes + p.beatBytes - 1) / p.beatBytes
              assert(stored == (lines * p.beatBytes).min(4096), s"stored $stored bytes of a $bytes-byte load")
              drv.serve(base, stored, 150)
            }
            // Full rate: every port answers once per cycle; shared ports serve whoever asks.
            val groups = StorePort.assign(clients, copies)
            StoreDriver.checkRate(groups, drv.saturate(0x14000L, warm = 20, cycles = 200), 200, _ => true)
            val some = (0 until clients).toSet - 1
            StoreDriver.checkRate(groups, drv.saturate(0x14000L, warm = 20, cycles = 200, some), 200, some)
        }
      }
  }
}
