package rtaccel.axi

import chisel3._
import chisel3.util._

/** Widths of an AXI4 interface. Data is at least 256 bits (a 32-byte write
  * record is half a 512-bit beat) and a power of two; bursts are INCR of
  * full-width beats.
  */
case class Axi4Params(addrBits: Int = 32, dataBits: Int = 512, idBits: Int = 6) {
  require(addrBits >= 12 && addrBits <= 64, s"Axi4Params: addrBits must be in 12..64, got $addrBits")
  require(
    dataBits >= 256 && dataBits <= 1024 && Integer.bitCount(dataBits) == 1,
    s"Axi4Params: dataBits must be a power of two in 256..1024, got $dataBits"
  )
  require(idBits >= 1 && idBits <= 16, s"Axi4Params: idBits must be in 1..16, got $idBits")
  val beatBytes: Int = dataBits / 8

  /** AxSIZE of a full-width beat: log2(bytes per beat) (6 for 512 bits). */
  val fullSize: Int = log2Ceil(beatBytes)
}

object Axi4 {
  val BurstIncr: Int = 1
  val RespOkay: Int = 0

  /** AxCACHE 0b0011: normal non-cacheable bufferable, what Xilinx's IP uses towards a MIG. */
  val CacheNormal: Int = 3

  /** Bursts never cross this boundary (AXI4 spec A3.4.1). */
  val BoundaryBytes: Int = 4096

  /** Most beats in an INCR burst (AxLEN = 255). */
  val MaxBurstBeats: Int = 256
}

/** AW or AR: one burst's address and shape. */
class Axi4Addr(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val addr = UInt(p.addrBits.W)
  val len = UInt(8.W)
  val size = UInt(3.W)
  val burst = UInt(2.W)
  val lock = Bool()
  val cache = UInt(4.W)
  val prot = UInt(3.W)
  val qos = UInt(4.W)
}

object Axi4Addr {

  /** An INCR burst of `beats` full-width beats (1..256) at `addr`. */
  def incr(p: Axi4Params, id: UInt, addr: UInt, beats: UInt): Axi4Addr = {
    val a = Wire(new Axi4Addr(p))
    a.id := id
    a.addr := addr
    a.len := beats - 1.U
    a.size := p.fullSize.U
    a.burst := Axi4.BurstIncr.U
    a.lock := false.B
    a.cache := Axi4.CacheNormal.U
    a.prot := 0.U
    a.qos := 0.U
    a
  }
}

class Axi4W(p: Axi4Params) extends Bundle {
  val data = UInt(p.dataBits.W)
  val strb = UInt(p.beatBytes.W)
  val last = Bool()
}

class Axi4B(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val resp = UInt(2.W)
}

class Axi4R(p: Axi4Params) extends Bundle {
  val id = UInt(p.idBits.W)
  val data = UInt(p.dataBits.W)
  val resp = UInt(2.W)
  val last = Bool()
}

/** An AXI4 master's side of the five channels (Chisel form of m_axi_*). */
class Axi4Master(val p: Axi4Params) extends Bundle {
  def this(sys: rtaccel.system.SystemConfig) = this(sys.axi)
  val aw = Decoupled(new Axi4Addr(p))
  val w = Decoupled(new Axi4W(p))
  val b = Flipped(Decoupled(new Axi4B(p)))
  val ar = Decoupled(new Axi4Addr(p))
  val r = Flipped(Decoupled(new Axi4R(p)))
}
