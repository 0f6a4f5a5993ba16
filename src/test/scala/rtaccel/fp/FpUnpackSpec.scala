package rtaccel.fp

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends

/** The adder's align step: `shiftRightSticky` (its sticky bit from
  * `anyBelow`) and `belowMask`, for every shift amount an input port of the
  * width can carry. The adders that use them are checked in FpUnitsSpec.
  */
class FpUnpackSpec extends AnyFlatSpec with ChiselScalatestTester {
  private class Align(w: Int, amountBits: Int) extends Module {
    val io = IO(new Bundle {
      val x = Input(UInt(w.W))
      val amount = Input(UInt(amountBits.W))
      val shifted = Output(UInt(w.W))
      val sticky = Output(Bool())
      val mask = Output(UInt(w.W))
    })
    private val (shifted, sticky) = FpUnpack.shiftRightSticky(io.x, io.amount)
    io.shifted := shifted
    io.sticky := sticky
    io.mask := FpUnpack.belowMask(w, io.amount)
  }

  // 27 bits: an FP32 significand with the adder's three extra bits. Amounts of
  // 4 bits (narrower than the decode's low part) and 9 (FP32's distance); also
  // widths whose sticky decode has no block level (3 bits) or a short one (8).
  for ((w, amountBits) <- Seq((27, 4), (27, 9), (3, 4), (8, 5))) {
    "FpUnpack.shiftRightSticky" should s"shift and find the dropped bits of $w bits, for every $amountBits-bit amount" in {
      test(new Align(w, amountBits)).withAnnotations(Backends.treadle) { dut =>
        val ones = (BigInt(1) << w) - 1
        val xs = (Seq(ones, BigInt("5a5a5a5", 16) & ones, BigInt(0)) ++ (0 until w).map(BigInt(1) << _)).distinct
        for (amount <- 0 until (1 << amountBits); x <- xs) {
          dut.io.x.poke(x.U)
          dut.io.amount.poke(amount.U)
          val want = (BigInt(1) << (amount min w)) - 1
          assert(dut.io.mask.peek().litValue == want, s"belowMask($w, $amount)")
          val dropped = x & want
          assert(dut.io.sticky.peek().litValue == (if (dropped != 0) 1 else 0), s"sticky($x >> $amount)")
          assert(dut.io.shifted.peek().litValue == (x >> amount), s"$x >> $amount")
        }
      }
    }
  }
}
