package rtaccel.fp

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** For each mode set, an [[FpRecipPair]] (two modes) or an [[FpRecipModes]]
  * (three) beside the single-mode [[FpRecip]]s on a shared operand: one
  * Verilator build per format.
  */
class FpRecipPairHarness(val fmt: FloatFormat, val modes: Seq[Seq[RoundingMode]]) extends Module {
  private val widest = modes.map(_.size).max
  val io = IO(new Bundle {
    val in = Flipped(Valid(new FpUnaryIn(fmt, false)))

    /** Per mode set: the shared unit's results, then the single-mode units' (unused places 0). */
    val out = Vec(modes.size, Valid(Vec(2 * widest, UInt(fmt.width.W))))
  })
  for ((ms, o) <- modes.zip(io.out)) {
    val (valid, shared) = if (ms.size == 2) {
      val pair = Module(new FpRecipPair(fmt, ms(0), ms(1)))
      pair.io.in := io.in
      (pair.io.out.valid, Seq(pair.io.out.bits.lo, pair.io.out.bits.hi))
    } else {
      val unit = Module(new FpRecipModes(fmt, ms))
      unit.io.in := io.in
      (unit.io.out.valid, unit.io.out.bits.toSeq)
    }
    val singles = ms.map(m => Module(new FpRecip(fmt, Some(m))))
    singles.foreach(_.io.in := io.in)
    def padded(xs: Seq[UInt]) = xs ++ Seq.fill(widest - xs.size)(0.U(fmt.width.W))
    o.valid := valid
    o.bits := VecInit(padded(shared) ++ padded(singles.map(_.io.out.bits)))
  }
}

class FpRecipPairSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FpRecipPair"

  import RoundingMode._

  /** The split box lanes' pair, one with the other two modes, and RayPrep's three (FpRecipModes). */
  private val modes = Seq(Seq(RTZ, RUP), Seq(RNE, RDN), Seq(RTZ, RUP, RNE))

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
          val widest = modes.map(_.size).max
          for ((ms, port) <- modes.zip(dut.io.out)) {
            assert(port.valid.peek().litToBoolean)
            val got = port.bits.map(_.peek().litValue)
            val want = ms.map(FpModel.recip(fmt, _, a))
            val (shared, singles) = (got.take(ms.size), got.slice(widest, widest + ms.size))
            def hex(x: BigInt) = "0x" + x.toString(16)
            assert(
              shared == want && singles == want,
              s"1/${hex(a)} ${fmt.name} (${ms.mkString(", ")}): shared unit ${shared.map(hex)}, single " +
                s"${singles.map(hex)}, model ${want.map(hex)}"
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

  it should "round every e4m3 operand in (RTZ, RUP), (RNE, RDN) and (RTZ, RUP, RNE) as FpRecip and the model do (exhaustive)" in {
    val fmt = FloatFormat(4, 3)
    run(fmt, (0 until (1 << fmt.width)).map(BigInt(_)))
  }

  it should "match on FP32: corners, powers of two, subnormals whose reciprocal overflows, 100,000 random values" in
    Seeded("FpRecipPairSpec.fp32") { rnd =>
      val fmt = FloatFormat.FP32
      run(fmt, (edges(fmt) ++ Seq.fill(100000)(FpOperands.single(fmt, rnd))).toIndexedSeq)
    }
}
