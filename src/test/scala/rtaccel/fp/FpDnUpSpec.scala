package rtaccel.fp

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

/** The dual-rounding units (add, sub, mul) beside the single-mode RDN and RUP
  * units on shared operands: one Verilator build per format.
  */
class FpDnUpHarness(val fmt: FloatFormat) extends Module {
  private def w = UInt(fmt.width.W)
  val io = IO(new Bundle {
    val in = Flipped(Valid(new FpBinaryIn(fmt, false)))

    /** add, sub, mul: dual unit (dn, up), then single RDN and RUP units. */
    val add = Valid(Vec(4, w))
    val sub = Valid(Vec(4, w))
    val mul = Valid(Vec(4, w))
  })
  private def drive[T <: Data](u: FpUnitIO[FpBinaryIn, T]): FpUnitIO[FpBinaryIn, T] = { u.in := io.in; u }
  private def row(
      dual: FpUnitIO[FpBinaryIn, FpDnUp],
      dn: FpUnitIO[FpBinaryIn, UInt],
      up: FpUnitIO[FpBinaryIn, UInt]
  ) = {
    val o = Wire(Valid(Vec(4, w)))
    o.valid := dual.out.valid
    o.bits := VecInit(drive(dual).out.bits.dn, dual.out.bits.up, drive(dn).out.bits, drive(up).out.bits)
    o
  }
  import RoundingMode.{RDN, RUP}
  io.add := row(
    Module(new FpAddDnUp(fmt)).io,
    Module(new FpAdd(fmt, Some(RDN))).io,
    Module(new FpAdd(fmt, Some(RUP))).io
  )
  io.sub := row(
    Module(new FpAddDnUp(fmt, subtract = true)).io,
    Module(new FpAdd(fmt, Some(RDN), subtract = true)).io,
    Module(new FpAdd(fmt, Some(RUP), subtract = true)).io
  )
  io.mul := row(
    Module(new FpMulDnUp(fmt)).io,
    Module(new FpMul(fmt, Some(RDN))).io,
    Module(new FpMul(fmt, Some(RUP))).io
  )
}

class FpDnUpSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "FpAddDnUp and FpMulDnUp"

  /** Streams `pairs` one per cycle; every dual result must equal the single-mode unit's and FpModel's. */
  private def run(fmt: FloatFormat, pairs: IndexedSeq[(BigInt, BigInt)]): Unit =
    test(new FpDnUpHarness(fmt)).withAnnotations(Backends.verilator) { dut =>
      import RoundingMode.{RDN, RUP}
      val ops: Seq[(String, Valid[Vec[UInt]], (RoundingMode, BigInt, BigInt) => BigInt)] = Seq(
        ("add", dut.io.add, FpModel.add(fmt, _, _, _)),
        ("sub", dut.io.sub, FpModel.sub(fmt, _, _, _)),
        ("mul", dut.io.mul, FpModel.mul(fmt, _, _, _))
      )
      val next = Array.fill(ops.size)(0)
      var cycle = 0
      while (next.exists(_ < pairs.size)) {
        val send = cycle < pairs.size
        dut.io.in.valid.poke(send.B)
        if (send) {
          dut.io.in.bits.a.poke(pairs(cycle)._1.U)
          dut.io.in.bits.b.poke(pairs(cycle)._2.U)
        }
        for (((name, port, model), j) <- ops.zipWithIndex if port.valid.peek().litToBoolean) {
          val (a, b) = pairs(next(j))
          val got = port.bits.map(_.peek().litValue)
          val want = Seq(model(RDN, a, b), model(RUP, a, b))
          def hex(x: BigInt) = "0x" + x.toString(16)
          val msg = s"$name ${fmt.name} a=${hex(a)} b=${hex(b)}: dual ${got.take(2).map(hex)}, " +
            s"single ${got.drop(2).map(hex)}, model ${want.map(hex)}"
          assert(got == want ++ want, msg)
          next(j) += 1
        }
        dut.clock.step()
        cycle += 1
        assert(cycle < pairs.size + 100, s"results stopped: ${next.toSeq} of ${pairs.size}")
      }
      assert(next.forall(_ == pairs.size))
    }

  it should "round every e4m3 operand pair down and up as the single-mode units and the model do (exhaustive)" in {
    val fmt = FloatFormat(4, 3)
    val all = (0 until (1 << fmt.width)).map(BigInt(_))
    run(fmt, for (a <- all; b <- all) yield (a, b))
  }

  it should "match on FP32: every pair of corners (zeros, infinities, NaNs, subnormals, overflow) and 100,000 random pairs" in
    Seeded("FpDnUpSpec.fp32") { rnd =>
      val fmt = FloatFormat.FP32
      run(fmt, (FpOperands.cornerPairs(fmt) ++ Seq.fill(100000)(FpOperands.pair(fmt, rnd))).toIndexedSeq)
    }
}
