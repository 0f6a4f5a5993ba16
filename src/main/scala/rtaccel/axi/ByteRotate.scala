package rtaccel.axi

import chisel3._
import chisel3.util._

/** Rotates a vector of bytes right by a byte count: result byte j is input
  * byte (j + by) mod n. A log-shifter (log2 n stages of 2:1 muxes) rather
  * than n n:1 byte muxes: for a 64-byte beat that is six mux levels instead
  * of 64 wide ones.
  */
object ByteRotate {
  def right(data: UInt, by: UInt): UInt = {
    val bytes = data.getWidth / 8
    require(
      data.getWidth % 8 == 0 && Integer.bitCount(bytes) == 1,
      s"ByteRotate: width ${data.getWidth} is not a power-of-two number of bytes"
    )
    (0 until log2Ceil(bytes)).foldLeft(data) { (x, s) =>
      val bits = 8 << s
      val rotated = if (bits == x.getWidth) x else Cat(x(bits - 1, 0), x(x.getWidth - 1, bits))
      Mux(by(s), rotated, x)
    }
  }
}

/** Burst arithmetic: bursts never cross a 4 KB boundary (AXI4 A3.4.1). */
object BurstMath {

  /** Whole beats from the beat-aligned `addr` up to the next 4 KB boundary (1 .. 4096 / beatBytes). */
  def beatsToBoundary(p: Axi4Params, addr: UInt): UInt = {
    val pageBits = log2Ceil(Axi4.BoundaryBytes)
    val beatBits = log2Ceil(p.beatBytes)
    (Axi4.BoundaryBytes.U((pageBits + 1).W) - addr(pageBits - 1, 0)) >> beatBits
  }

  /** Beats of a full-width INCR transfer covering `bytes` bytes at byte address `addr`. */
  def beatsCovering(p: Axi4Params, addr: UInt, bytes: UInt): UInt = {
    val beatBits = log2Ceil(p.beatBytes)
    ((addr(beatBits - 1, 0) +& bytes - 1.U) >> beatBits) + 1.U
  }
}
