package rtaccel.axi

import chisel3._
import chisel3.util._

/** AXI4-Lite address (AW or AR) payload. */
class AxiLiteAddr(addrBits: Int) extends Bundle {
  val addr = UInt(addrBits.W)
  val prot = UInt(3.W)
}

class AxiLiteW(dataBits: Int) extends Bundle {
  val data = UInt(dataBits.W)
  val strb = UInt((dataBits / 8).W)
}

class AxiLiteR(dataBits: Int) extends Bundle {
  val data = UInt(dataBits.W)
  val resp = UInt(2.W)
}

/** An AXI4-Lite port from the master's side (the slave takes it Flipped). */
class AxiLite(val addrBits: Int, val dataBits: Int) extends Bundle {
  val aw = Decoupled(new AxiLiteAddr(addrBits))
  val w = Decoupled(new AxiLiteW(dataBits))
  val b = Flipped(Decoupled(UInt(2.W)))
  val ar = Decoupled(new AxiLiteAddr(addrBits))
  val r = Flipped(Decoupled(new AxiLiteR(dataBits)))
}

object AxiResp {
  val Okay = 0
  val SlvErr = 2
}
