package rtaccel.fp

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** For each mode pair, an [[FpRecipPair]] beside the two single-mode
  * [[FpRecip]]s on a shared operand: one Verilator build per format.
  */
class FpRecipPairHarness(val fmt: FloatFormat, val modes: Seq[(RoundingMode, RoundingMode)]) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(Valid(new FpUnaryIn(fmt, false)))

    /** Per mode pair: the pair unit's lo and hi, then the single-mode units'. */
    val out = Vec(modes.size, Valid(Vec(4, UInt(fmt.width.W))))
  })
  for (((lo, hi), o) <- modes.zip(io.out)) {
    val pair = Module(new FpRecipPair(fmt, lo, hi))
    val singles = Seq(lo, hi).map(m => Module(new FpRecip(fmt, Some(m))))
    pair.io.in := io.in
    singles.foreach(_.io.in := io.in)
    o.valid := pair.io.out.valid
    o.bits := VecInit(Seq(pair.io.out.bits.lo, pair.io.out.bits.hi) ++ singles.map(_.io.out.bits))
  }
}

class FpRecipPairSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FpRecipPair"

  import RoundingMode._

  /** RayPrep's pair, and one with the other two modes. */
  private val modes = Seq((RTZ, RUP), (RNE, RDN))

  /** Streams `ops` one per cycle; both results of every pair unit must equal the single-mode units' and FpModel's. */
  private def run(fmt: FloatFormat, ops: IndexedSeq[BigInt]): Unit =
    test(new FpRecipPairHarness(fmt, modes)).withAnnotations(Backends.verilator) { dut =>
      var (cycle, next) = (0, 0)
      while (next < ops.size) {
        val send = cycle < ops.size
        dut.io.in.valid.poke(send.B)
        if (send) dut.io.in.bits.a.poke(ops(cycle).U)
        if (dut.io.out(0).valid.peek().litToBoolean) {
          val a = ops(next)
          for (((lo, hi), port) <- modes.zip(dut.io.out)) {
            assert(port.valid.peek().litToBoolean)
            val got = port.bits.map(_.peek().litValue)
            val want = Seq(FpModel.recip(fmt, lo, a), FpModel.recip(fmt, hi, a))
            def hex(x: BigInt) = "0x" + x.toString(16)
            assert(
              got == want ++ want,
              s"1/${hex(a)} ${fmt.name} ($lo, $hi): pair ${got.take(2).map(hex)}, single ${got.drop(2).map(hex)}, " +
                s"model ${want.map(hex)}"
            )
          }
          next += 1
        }
        dut.clock.step()
        cycle += 1
        assert(cycle < ops.size + 100, s"results stopped: $next of ${ops.size}")
      }
    }

  /** Corners, every power of two, and the subnormals around the ones whose reciprocal overflows. */
  private def edges(fmt: FloatFormat): Seq[BigInt] = {
    val pow2 = (0 until fmt.maxExpField).map(e => fmt.pack(false, e, if (e == 0) 1 else 0)) ++
      (0 until fmt.manBits).map(k => fmt.pack(false, 0, BigInt(1) << k))
    val near = for (k <- 0 until fmt.manBits; d <- Seq(-1, 1)) yield fmt.pack(false, 0, (BigInt(1) << k) + d)
    val all = (pow2 ++ near).filter(_ > 0)
    (FpOperands.corners(fmt) ++ all ++ all.map(fmt.negate)).distinct
  }

  it should "round every e4m3 operand in (RTZ, RUP) and (RNE, RDN) as FpRecip and the model do (exhaustive)" in {
    val fmt = FloatFormat(4, 3)
    run(fmt, (0 until (1 << fmt.width)).map(BigInt(_)))
  }

  it should "match on FP32: corners, powers of two, subnormals whose reciprocal overflows, 100,000 random values" in
    Seeded("FpRecipPairSpec.fp32") { rnd =>
      val fmt = FloatFormat.FP32
      run(fmt, (edges(fmt) ++ Seq.fill(100000)(FpOperands.single(fmt, rnd))).toIndexedSeq)
    }
}
