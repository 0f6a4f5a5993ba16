package rtaccel.system

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** NodeStore alone (StoreDriver): filled from a SparseMemory of random bytes
  * under random arready and R gaps, then read by three clients (two storage
  * copies, one of them shared with the fill's port) with random valid and
  * ready: every read answered once, in order per client, with the DRAM
  * record and its tag; `hit` follows the rule (loaded, record-aligned
  * relative to base, below base + storedBytes) on random probes.
  */
class NodeStoreSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "NodeStore"

  private def hits(rec: Int)(a: Long, base: Long, stored: Long): Boolean =
    a >= base && a < base + stored && (a - base) % rec == 0

  for ((dataBits, rec) <- Seq((512, 32), (512, 128), (1024, 32))) {
    it should s"serve every read of a loaded store once, with DRAM's record ($dataBits-bit beats, $rec-byte records)" in
      Seeded(s"NodeStore.$dataBits.$rec") { rnd =>
        val StoreDriver.Bench(p, port, mem) = StoreDriver.bench(dataBits, rec, rnd)
        test(new NodeStore(p, port, clients = 3, capacityBytes = 4096, fillId = 7)).withAnnotations(Backends.treadle) {
          dut =>
            val drv = new StoreDriver(dut.io, dut.clock, p, rec, 7, mem, rnd, hits(rec))
            for ((base, bytes) <- Seq((0x10040L, 1000L), (0x14000L, 100000L))) {
              val stored = drv.load(base, bytes)
              val words = (bytes + rec.max(p.beatBytes) - 1) / rec.max(p.beatBytes)
              assert(stored == (words * rec.max(p.beatBytes)).min(4096), s"stored $stored bytes of a $bytes-byte load")
              drv.serve(base, stored, 150)
            }
        }
      }
  }
}
