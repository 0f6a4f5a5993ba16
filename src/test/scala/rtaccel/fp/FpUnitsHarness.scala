package rtaccel.fp

import chisel3._
import chisel3.util._

/** Latencies of the units in one [[FpUnitsHarness]]. */
case class FpHarnessLatencies(add: Int, mul: Int, div: Int, recip: Int, cmp: Int, conv: Int)

object FpHarnessLatencies {
  def defaults(fmt: FloatFormat): FpHarnessLatencies =
    FpHarnessLatencies(
      FpAdd.defaultLatency,
      FpMul.defaultLatency,
      FpDivCore.defaultLatency(fmt),
      FpRecipCore.defaultLatency(fmt),
      FpCompare.defaultLatency,
      FpConvert.defaultLatency
    )
}

/** Every unit of one format side by side on shared operands, so that a single
  * Verilator build tests them all: add, sub, mul, div, recip(a), compare,
  * fromF32 (the `f32` operand into `fmt`) and toF32 (`a` into FP32).
  */
class FpUnitsHarness(val fmt: FloatFormat, val rm: Option[RoundingMode], val lat: FpHarnessLatencies) extends Module {
  private val F32 = FloatFormat.FP32
  val io = IO(new Bundle {
    val in = Flipped(Valid(new FpBinaryIn(fmt, rm.isEmpty)))
    val f32 = Input(UInt(F32.width.W))
    val add = Valid(UInt(fmt.width.W))
    val sub = Valid(UInt(fmt.width.W))
    val mul = Valid(UInt(fmt.width.W))
    val div = Valid(UInt(fmt.width.W))
    val recip = Valid(UInt(fmt.width.W))
    val cmp = Valid(new FpCompareOut(fmt))
    val fromF32 = Valid(UInt(fmt.width.W))
    val toF32 = Valid(UInt(F32.width.W))
  })
  override def desiredName: String = s"FpUnitsHarness_${fmt.name}_${RoundingMode.tag(rm)}"

  private def binary(m: Module { val io: FpUnitIO[FpBinaryIn, UInt] }): Valid[UInt] = {
    m.io.in := io.in
    m.io.out
  }
  io.add := binary(Module(new FpAdd(fmt, rm, lat.add)))
  io.sub := binary(Module(new FpAdd(fmt, rm, lat.add, subtract = true)))
  io.mul := binary(Module(new FpMul(fmt, rm, lat.mul)))
  io.div := binary(Module(new FpDiv(fmt, rm, lat.div)))

  private val recip = Module(new FpRecip(fmt, rm, lat.recip))
  recip.io.in.valid := io.in.valid
  recip.io.in.bits.a := io.in.bits.a
  recip.io.in.bits.rm.foreach(_ := io.in.bits.rm.get)
  io.recip := recip.io.out

  private val cmp = Module(new FpCompare(fmt, lat.cmp))
  cmp.io.in.valid := io.in.valid
  cmp.io.in.bits.a := io.in.bits.a
  cmp.io.in.bits.b := io.in.bits.b
  io.cmp := cmp.io.out

  private val from = Module(new FpConvert(F32, fmt, rm, lat.conv))
  from.io.in.valid := io.in.valid
  from.io.in.bits.a := io.f32
  from.io.in.bits.rm.foreach(_ := io.in.bits.rm.get)
  io.fromF32 := from.io.out

  private val to = Module(new FpConvert(fmt, F32, rm, lat.conv))
  to.io.in.valid := io.in.valid
  to.io.in.bits.a := io.in.bits.a
  to.io.in.bits.rm.foreach(_ := io.in.bits.rm.get)
  io.toF32 := to.io.out
}
