package rtaccel.axi

import chisel3._
import chisel3.util._
import rtaccel.system.SystemConfig

// PLACEHOLDER for the sys-mem helper's rtaccel.axi Axi4 bundles (system contract):
// the same shape, deleted when branch sysmem's bundles are merged.

class Axi4Addr(sys: SystemConfig) extends Bundle {
  val id    = UInt(sys.axiIdBits.W)
  val addr  = UInt(sys.axiAddrBits.W)
  val len   = UInt(8.W)
  val size  = UInt(3.W)
  val burst = UInt(2.W)
  val lock  = Bool()
  val cache = UInt(4.W)
  val prot  = UInt(3.W)
  val qos   = UInt(4.W)
}

class Axi4W(sys: SystemConfig) extends Bundle {
  val data = UInt(sys.axiDataBits.W)
  val strb = UInt((sys.axiDataBits / 8).W)
  val last = Bool()
}

class Axi4B(sys: SystemConfig) extends Bundle {
  val id   = UInt(sys.axiIdBits.W)
  val resp = UInt(2.W)
}

class Axi4R(sys: SystemConfig) extends Bundle {
  val id   = UInt(sys.axiIdBits.W)
  val data = UInt(sys.axiDataBits.W)
  val resp = UInt(2.W)
  val last = Bool()
}

/** The m_axi side of the system, master's view. */
class Axi4Master(sys: SystemConfig) extends Bundle {
  val aw = Decoupled(new Axi4Addr(sys))
  val w  = Decoupled(new Axi4W(sys))
  val b  = Flipped(Decoupled(new Axi4B(sys)))
  val ar = Decoupled(new Axi4Addr(sys))
  val r  = Flipped(Decoupled(new Axi4R(sys)))
}
