package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.mem.MemPortParams
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends
import rtaccel.sim.axi.AxiMemoryParams
import rtaccel.sim.mem.LatencyNs

import scala.collection.mutable
import scala.util.Random

/** MemoryFabric against AxiMemoryModel: random record reads of every size and
  * alignment (4 KB straddles included) from clients with random back-pressure,
  * a slave that reorders, interleaves, stalls every channel and checks the
  * protocol; every response compared byte for byte with memory and every
  * request answered exactly once; writes checked in memory; node-store hits
  * served without DRAM traffic, bit-exact; triangle-store hits (48-byte
  * records straddling lines included) likewise.
  */
class MemoryFabricSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "MemoryFabric"

  import MemoryFabricSpec._

  it should "elaborate with the default SystemConfig and the cores' clients (nodes, triangles, ray lines)" in {
    val sys0 = SystemConfig()
    val node = rtaccel.traversal.PrepFetch.port(sys0.core).copy(tagBits = sys0.core.rayIdBits + 1)
    val tri = rtaccel.leaf.LeafIntersect.port(sys0.core)
    val ports = Seq.fill(sys0.cores)(Seq(node, tri)).flatten :+ MemPortParams(sys0.axiAddrBits, 4, 64)
    val flags = Seq.fill(sys0.cores)(Seq(true, false)).flatten :+ false
    val triFlags = Seq.fill(sys0.cores)(Seq(false, true)).flatten :+ false
    val chirrtl = circt.stage.ChiselStage.emitCHIRRTL(new MemoryFabric(sys0, ports, flags, triFlags))
    assert(chirrtl.contains(
      s"MemoryFabric_r${ports.size}_id${sys0.axiIdBits}_ns${sys0.nodeStoreBytes / 1024}k_ts${sys0.triStoreBytes / 1024}k"
    ))
  }

  // One Verilator build for every phase: the build is most of the spec's time.
  it should "answer random reads of every size and alignment exactly once and byte-exact under reordering and back-pressure, " +
    "write records, serve node- and triangle-store hits on chip at a fixed latency, and flag SLVERR" in Seeded(
      "MemoryFabric"
    ) { rnd =>
      test(new MemoryFabric(sys, readers, nodeFlags, triFlags)).withAnnotations(Backends.verilator) { dut =>
        val env = new FabricEnv(dut, rnd, AxiMemoryParams(errorAt = _ == ErrorAddr).harsh(rnd.nextLong()))
        val m = env.mem.model

        // 1. Random traffic; the store's fill overlaps it, so node reads go to DRAM until it is done.
        env.startLoad(NodeBase, StoreLoadBytes)
        env.run(requestsPerClient = 150, writes = 150)
        assert(
          m.reorderedBursts > 0 && m.interleavedBeats > 0,
          s"the slave never reordered (${m.reorderedBursts}) or interleaved (${m.interleavedBeats})"
        )
        assert(env.straddles > 0, "no read straddled a 4 KB boundary")
        assert(
          env.storeRequests > 0 && env.storeRequests < env.nodeRequests,
          s"${env.storeRequests} of ${env.nodeRequests} node reads hit: the mix misses a case"
        )
        dut.io.axiError.expect(false.B)
        assert(
          dut.io.store.storedBytes.peek().litValue == StoreBytes,
          "storedBytes: the load asked for more than the capacity"
        )
        val hits = dut.io.stats.nodeStoreHits.peek().litValue
        val misses = dut.io.stats.nodeStoreMisses.peek().litValue
        assert(
          hits == env.storeRequests && misses == env.nodeRequests - env.storeRequests,
          s"node store: $hits hits / $misses misses, expected ${env.storeRequests} / ${env.nodeRequests - env.storeRequests}"
        )
        assert(dut.io.stats.readBeats.peek().litValue == m.readBeats, "readBeats differs from the beats the slave sent")
        assert(
          dut.io.stats.writeBeats.peek().litValue == m.writeBeats,
          "writeBeats differs from the beats the slave took"
        )
        env.quiet(cycles = 300) // no response may follow the last answer

        // 1b. The triangle store fills (after the node store, as the scene loader orders them) under random traffic.
        env.startLoad(TriBase, TriLoadBytes, tri = true)
        env.run(requestsPerClient = 150, writes = 50)
        dut.io.axiError.expect(false.B)
        assert(
          dut.io.triStore.storedBytes.peek().litValue == TriStoreBytes,
          "triangle storedBytes: the load asked for more than the capacity"
        )
        assert(
          env.triStoreRequests > 0 && env.triStoreRequests < env.triRequests,
          s"${env.triStoreRequests} of ${env.triRequests} triangle reads hit: the mix misses a case"
        )
        assert(
          dut.io.stats.triStoreHits.peek().litValue == env.triStoreRequests,
          s"triangle store: ${dut.io.stats.triStoreHits.peek().litValue} hits, expected ${env.triStoreRequests}"
        )
        env.quiet(cycles = 300)
        // Every whole triangle of the triangle store, back to back on both triangle clients.
        val triBursts = m.readBursts
        val triLat = env.storeOnly(records = (TriStoreBytes - 48) / 48 + 1, pair = (2, 6), base = TriBase, stride = 48)
        assert(m.readBursts == triBursts, "a triangle-store hit went to DRAM")
        assert(
          triLat.forall(_ == TriStoreLatency),
          s"triangle-store latencies ${triLat.distinct}, expected $TriStoreLatency"
        )

        // 2. Every node of the store, back to back on both node clients: no DRAM read, a fixed latency.
        val burstsBefore = m.readBursts
        val latencies = env.storeOnly(records = StoreBytes / NodeBytes)
        assert(m.readBursts == burstsBefore, "a node-store hit went to DRAM")
        assert(
          latencies.forall(_ == NodeStoreLatency),
          s"node-store latencies ${latencies.distinct}, expected $NodeStoreLatency"
        )

        // 3. A SLVERR read: the record still comes back (its client does not hang) and axiError is set.
        env.readOne(client = 3, addr = ErrorAddr)
        dut.io.axiError.expect(true.B, "a SLVERR read left axiError low")
        println(
          s"MemoryFabricSpec: seed ${Seeded.seedFor("MemoryFabric")}, ${env.cycle} cycles, ${env.nodeRequests + env.otherRequests} reads " +
            s"(${env.storeRequests} node-store hits, ${env.triStoreRequests} of ${env.triRequests} triangle reads from the triangle store, " +
            s"${env.straddles} straddling 4 KB), ${env.writesSent} writes, " +
            s"${m.readBursts} read bursts (${m.reorderedBursts} reordered, ${m.interleavedBeats} beats interleaved)"
        )
      }
    }
}

object MemoryFabricSpec {

  /** A small system: 4 ID bits (15 read slots), a 4 KB node store (32 wide-4 nodes), a 4 KB triangle store (85 triangles). */
  val StoreBytes = 4096
  val TriStoreBytes = 4096
  val sys: SystemConfig = SystemConfig(axiIdBits = 4, nodeStoreBytes = StoreBytes, triStoreBytes = TriStoreBytes)
  val NodeBytes = 128

  /** Two node clients (wide-4 nodes), a triangle client, byte-aligned records of 64, 200 and 32 bytes, a second
    * triangle client. */
  val readers: Seq[MemPortParams] = Seq(
    MemPortParams(32, 5, NodeBytes),
    MemPortParams(32, 5, NodeBytes),
    MemPortParams(32, 4, 48),
    MemPortParams(32, 3, 64),
    MemPortParams(32, 4, 200),
    MemPortParams(32, 3, 32),
    MemPortParams(32, 4, 48)
  )
  val nodeFlags: Seq[Boolean] = Seq(true, true, false, false, false, false, false)
  val triFlags: Seq[Boolean] = Seq(false, false, true, false, false, false, true)

  /** The node array starts 320 bytes below a 4 KB boundary, so the fill's bursts must split there, and 64 bytes
    * into a 128-byte beat, so a 1024-bit m_axi's fill (AXI_DATA_BITS=1024) must realign (NodeStore). */
  val NodeBase: Long = 0x2ec0
  val NodeCount = 64

  /** The triangle array: 120 triangles (5,760 bytes, more than the triangle store holds). At 1024 bits it starts
    * 64 bytes into a beat, so the triangle store's fill realigns too. */
  val TriBase: Long = 0x6040
  val TriLoadBytes: Int = 120 * 48
  val StoreLoadBytes: Int = NodeCount * NodeBytes

  /** Reads come from [0, ReadSpan); writes go to [WriteBase, WriteBase + WriteSpan). */
  val ReadSpan = 0x8000
  val WriteBase: Long = 0x10000
  val WriteSpan = 0x2000

  /** The slave answers SLVERR here (outside the random reads' span). */
  val ErrorAddr: Long = 0x8000

  /** Request accepted in cycle t, response offered from t + NodeStore.Latency. */
  val NodeStoreLatency: Int = rtaccel.system.NodeStore.Latency

  /** The same for the triangle store (its realigned record is registered): TriStore.Latency. */
  val TriStoreLatency: Int = rtaccel.system.TriStore.Latency
}
