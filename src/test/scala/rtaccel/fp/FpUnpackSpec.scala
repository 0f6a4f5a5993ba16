package rtaccel.fp

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.Backends

/** The normalisers' helpers: `leadingZeros` of every nonzero value of a few widths (powers of two and not),
  * and `shiftLeftMsbFirst` for every amount its port can carry (amounts past the width included). The units
  * that use them are checked in FpUnitsSpec.
  */
class FpUnpackSpec extends AnyFlatSpec with ChiselScalatestTester {
  private class Helpers(w: Int, amountBits: Int) extends Module {
    val io = IO(new Bundle {
      val x = Input(UInt(w.W))
      val amount = Input(UInt(amountBits.W))
      val lz = Output(UInt(log2Ceil(w).W))
      val shifted = Output(UInt(w.W))
    })
    io.lz := FpUnpack.leadingZeros(io.x)
    io.shifted := FpUnpack.shiftLeftMsbFirst(io.x, io.amount)
  }
  private def log2Ceil(n: Int): Int = chisel3.util.log2Ceil(n)

  for ((w, amountBits) <- Seq((8, 4), (11, 4), (28, 5), (5, 3))) {
    "FpUnpack.leadingZeros and shiftLeftMsbFirst" should s"count and shift $w bits, for every $amountBits-bit amount" in {
      test(new Helpers(w, amountBits)).withAnnotations(Backends.treadle) { dut =>
        val ones = (BigInt(1) << w) - 1
        val xs = if (w <= 11) (1 until (1 << w)).map(BigInt(_))
        else
          (Seq(ones, BigInt("5a5a5a5", 16) & ones) ++ (0 until w).flatMap(k => Seq(BigInt(1) << k, ones >> k))).distinct
        for (x <- xs) {
          dut.io.x.poke(x.U)
          assert(dut.io.lz.peek().litValue == w - x.bitLength, s"leadingZeros($x)")
          for (amount <- 0 until (1 << amountBits)) {
            dut.io.amount.poke(amount.U)
            assert(dut.io.shifted.peek().litValue == ((x << amount) & ones), s"$x << $amount")
          }
        }
      }
    }
  }
}
