package rtaccel.system

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** NodeStore alone (StoreDriver): filled from a SparseMemory of random bytes
  * under random arready and R gaps, then read by three clients with random
  * valid and ready, on one copy of the storage (its two ports shared by
  * three or four clients, StorePort) and on two (a port per client, or five
  * clients sharing the copies' ports; the second copy's port A also the
  * fill's): every
  * read answered once, in order per client, with the DRAM
  * record and its tag; `hit` follows the rule (loaded, record-aligned
  * relative to base, below base + storedBytes) on random probes; saturated,
  * the ports answer once a cycle each, shared evenly among the clients that
  * ask.
  */
class NodeStoreSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "NodeStore"

  private def hits(rec: Int)(a: Long, base: Long, stored: Long): Boolean =
    a >= base && a < base + stored && (a - base) % rec == 0

  for (
    (dataBits, rec, copies, clients) <-
      Seq((1024, 32, 1, 3), (512, 128, 2, 3), (512, 32, 1, 4), (512, 128, 2, 5))
  ) {
    it should s"serve every read of a loaded store once, with DRAM's record ($dataBits-bit beats, $rec-byte records, " +
      s"$copies ${if (copies == 1) "copy" else "copies"} for $clients clients)" in
      Seeded(s"NodeStore.$dataBits.$rec.$copies.$clients") { rnd =>
        val StoreDriver.Bench(p, port, mem) = StoreDriver.bench(dataBits, rec, rnd)
        test(
          new NodeStore(p, port, clients = clients, capacityBytes = 4096, fillId = 7, copies = copies)
        ).withAnnotations(
          Backends.treadle
        ) {
          dut =>
            val drv = new StoreDriver(dut.io, dut.clock, p, rec, 7, mem, rnd, hits(rec))
            for ((base, bytes) <- Seq((0x10040L, 1000L), (0x14000L, 100000L))) {
              val stored = drv.load(base, bytes)
              val words = (bytes + rec.max(p.beatBytes) - 1) / rec.max(p.beatBytes)
              assert(stored == (words * rec.max(p.beatBytes)).min(4096), s"stored $stored bytes of a $bytes-byte load")
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
