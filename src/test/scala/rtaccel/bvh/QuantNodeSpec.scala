package rtaccel.bvh

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded
import rtaccel.{AccelConfig, BoxTest}

/** A quantized record's slot words as a staged fetch computes them: the record with its slots' counts
  * (BvhNode.record, QuantNode.befores), then the words (BvhNode.words), here in one cycle.
  */
class QuantWordsTop(cfg: AccelConfig) extends Module {
  val io = IO(new Bundle {
    val data = Input(UInt((cfg.layout.nodeBytes * 8).W))
    val word0 = Output(Vec(cfg.boxLanes, UInt(32.W)))
    val word1 = Output(Vec(cfg.boxLanes, UInt(32.W)))
  })
  private val w = BvhNode.words(cfg, BvhNode.record(cfg, io.data))
  io.word0 := VecInit(w.slots.map(_.word0))
  io.word1 := VecInit(w.slots.map(_.word1))
}

/** The quantized decode's child references (word0, word1) against QuantNode.decodeSoft, bit for bit, on random
  * records whose meta bytes mix empty, inner, leaf (counts up to 127) and corrupt kinds, so every slot's counts
  * of the inner slots and leaf triangles before it (QuantNode.befores) are exercised in 4q and 8q. The grid box
  * test keeps the planes raw, so no FP32 adder slows the simulation.
  */
class QuantNodeSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "QuantNode's child references"

  for (k <- Seq(4, 8)) {
    val cfg = AccelConfig(layout = BvhLayout.Wide(k, quantized = true), boxTest = BoxTest.Grid)
    it should s"match decodeSoft's word0 and word1 on random records (${cfg.layout.name})" in Seeded(
      s"QuantNode.refs.$k"
    ) { rnd =>
      test(new QuantWordsTop(cfg)).withAnnotations(Backends.treadle) { dut =>
        for (n <- 0 until 2000) {
          val bytes = Array.fill(cfg.layout.nodeBytes)(rnd.nextInt(256))
          // Bases near 2^32 too, so the index adds wrap.
          if (rnd.nextBoolean()) for (i <- 16 until 24) bytes(i) = 0xff - rnd.nextInt(2)
          // Mostly leaves with large counts (the longest sums), some inner and empty slots, a few corrupt bytes.
          for (s <- 0 until k) bytes(QuantNode.FixedBytes + s) = rnd.nextInt(10) match {
            case 0     => QuantNode.MetaEmpty
            case 1 | 2 => QuantNode.MetaInner
            case 3     => rnd.nextInt(256)
            case 4     => 0xff
            case _     => QuantNode.MetaLeaf | rnd.nextInt(128)
          }
          val soft = QuantNode.decodeSoft(k, bytes.toIndexedSeq, planes = false)
          dut.io.data.poke(bytes.zipWithIndex.map { case (b, i) => BigInt(b) << (8 * i) }.sum.U)
          for (s <- 0 until k) {
            val meta = f"record $n, slot $s (meta 0x${bytes(QuantNode.FixedBytes + s)}%02x)"
            dut.io.word0(s).expect(soft(s).word0.U, s"$meta: word0")
            dut.io.word1(s).expect(soft(s).word1.U, s"$meta: word1")
          }
        }
      }
    }
  }
}
