package rtaccel.system

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.scene.MemoryImage
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.util.Random

/** SceneLoader alone. The header port answers after a random delay with
  * random ready, and the two stores (Scala models of NodeStoreLoad: `done`
  * falls at `start`, rises a random number of cycles later) finish at random.
  * For a good header and for each way a header can be wrong, the reference is
  * plain Scala: one header read at SCENE_BASE, then (good) one node-store load
  * of the node array and, with a triangle store, one triangle-store load of
  * the triangle array, `ready` and one `finished` pulse; or (bad) the error
  * code, no store load and one `finished` pulse. A start while busy is ignored.
  */
class SceneLoaderSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "SceneLoader"

  private def le32(bytes: Array[Byte], at: Int): Long =
    (0 until 4).map(i => (bytes(at + i) & 0xffL) << (8 * i)).sum

  /** A header: the fields SceneLoader reads, as docs/memory-format.md places them. */
  private def header(sys: SystemConfig, rnd: Random, spoil: Int): BigInt = {
    val nodeOffset = 64L * (1 + rnd.nextInt(4))
    val triOffset = nodeOffset + 64L * (1 + rnd.nextInt(1000))
    val w = Array.fill(16)(0L)
    w(0) = le32(MemoryImage.Magic, 0); w(1) = le32(MemoryImage.Magic, 4)
    w(2) = MemoryImage.Version
    w(4) = 1 + rnd.nextInt(100000)
    w(5) = nodeOffset; w(6) = triOffset
    w(7) = sys.core.layout.nodeBytes; w(8) = MemoryImage.TriBytes
    w(10) = rnd.nextInt(sys.core.stackDepth + 1); w(11) = sys.core.layout.code
    spoil match {
      case 1 => w(1) ^= 1L << rnd.nextInt(32)
      case 2 => w(2) = MemoryImage.Version + 1
      case 3 => w(11) = sys.core.layout.code ^ 1
      case 4 => if (rnd.nextBoolean()) w(7) += 32 else w(8) = 32
      case 5 => w(6) += 16
      case 6 => w(10) = sys.core.stackDepth + 1
      case _ =>
    }
    w.zipWithIndex.map { case (v, k) => BigInt(v) << (32 * k) }.reduce(_ | _)
  }

  for (triStore <- Seq(256 * 1024, 0)) {
    it should s"read the header once, load the stores in turn, and report every header error (tri store $triStore bytes)" in
      Seeded(s"SceneLoader.$triStore") { rnd =>
        val sys = SystemConfig(triStoreBytes = triStore)
        test(new SceneLoader(sys)).withAnnotations(Backends.treadle) { dut =>
          // Each case: (scene base, header spoiled by error code k, or 0 for a good one), several times over.
          val cases = rnd.shuffle(Seq.tabulate(21)(i => i % 7) ++ Seq(-1, -1))
          var passed = false // a header has passed the checks since reset: the bases are valid from then on
          dut.io.basesValid.expect(false.B, "bases valid after reset")
          for ((spoil, i) <- cases.zipWithIndex) {
            val base = 0x100000L * (1 + i) + (if (spoil == -1) 32 else 0) // -1: a misaligned SCENE_BASE
            val hdr = header(sys, rnd, spoil.max(0))
            val hw = Array.tabulate(16)(k => ((hdr >> (32 * k)) & 0xffffffffL).toLong)
            val wantCode = if (spoil == -1) 5 else spoil
            dut.io.sceneBase.poke(base.U); dut.io.start.poke(true.B)
            dut.io.store.done.poke(true.B); dut.io.triStore.done.poke(true.B) // as a previous load left them
            dut.io.mem.req.ready.poke(false.B); dut.io.mem.resp.valid.poke(false.B)
            var reqs, nodeLoads, triLoads, finished = 0
            if (dut.io.finished.peek().litToBoolean) finished += 1 // a misaligned base fails at once
            dut.clock.step(); dut.io.start.poke(false.B)
            var respDue = -1L
            var nodeDone, triDone = -1L // cycle at which each store model raises done again
            var cycle = 0L
            while ((dut.io.busy.peek().litToBoolean || finished == 0) && cycle < 2000) {
              // A start while busy changes nothing.
              dut.io.start.poke((rnd.nextInt(10) == 0).B); dut.io.sceneBase.poke((base + 0x40000).U)
              val reqReady = rnd.nextBoolean()
              dut.io.mem.req.ready.poke(reqReady.B)
              val respValid = respDue >= 0 && cycle >= respDue
              dut.io.mem.resp.valid.poke(respValid.B); dut.io.mem.resp.bits.data.poke(hdr.U);
              dut.io.mem.resp.bits.tag.poke(0.U)
              dut.io.store.done.poke((nodeDone >= 0 && cycle >= nodeDone).B)
              dut.io.triStore.done.poke((triDone >= 0 && cycle >= triDone).B)
              dut.io.store.busy.poke(false.B); dut.io.triStore.busy.poke(false.B)
              dut.io.store.storedBytes.poke(0.U); dut.io.triStore.storedBytes.poke(0.U)

              if (reqReady && dut.io.mem.req.valid.peek().litToBoolean) {
                dut.io.mem.req.bits.addr.expect(base.U, "header address"); reqs += 1
                respDue = cycle + 1 + rnd.nextInt(20)
              }
              if (respValid && dut.io.mem.resp.ready.peek().litToBoolean) respDue = -1
              if (dut.io.store.start.peek().litToBoolean) {
                nodeLoads += 1; nodeDone = cycle + 1 + rnd.nextInt(30)
                dut.io.store.base.expect((base + hw(5)).U, "node store base");
                dut.io.store.bytes.expect((hw(6) - hw(5)).U, "node store bytes")
              }
              if (dut.io.triStore.start.peek().litToBoolean) {
                triLoads += 1; triDone = cycle + 1 + rnd.nextInt(30)
                dut.io.triStore.base.expect((base + hw(6)).U, "tri store base");
                dut.io.triStore.bytes.expect((hw(4) * MemoryImage.TriBytes).U, "tri store bytes")
              }
              if (dut.io.finished.peek().litToBoolean) finished += 1
              dut.clock.step(); cycle += 1
            }
            val what = s"case $i (error ${wantCode}, base 0x${base.toHexString})"
            dut.io.start.poke(false.B)
            assert(finished == 1, s"$what: $finished finished pulses")
            assert(reqs == (if (spoil == -1) 0 else 1), s"$what: $reqs header reads")
            val good = wantCode == 0
            assert(
              nodeLoads == (if (good) 1 else 0) && triLoads == (if (good && triStore > 0) 1 else 0),
              s"$what: $nodeLoads node-store and $triLoads triangle-store loads"
            )
            dut.io.ready.expect(good.B, s"$what: ready"); dut.io.error.expect((!good).B, s"$what: error")
            dut.io.errorCode.expect(wantCode.U, s"$what: error code")
            if (good) { dut.io.nodeBase.expect((base + hw(5)).U); dut.io.triBase.expect((base + hw(6)).U) }
            passed ||= good
            dut.io.basesValid.expect(passed.B, s"$what: bases valid")
          }
        }
      }
  }
}
