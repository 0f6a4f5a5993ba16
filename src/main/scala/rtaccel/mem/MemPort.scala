package rtaccel.mem

import chisel3._
import chisel3.util._

/** Geometry of one memory port: byte addresses in, whole records out.
  *
  * The accelerator asks for one record (a 32-byte BVH node or a 48-byte
  * triangle, see docs/memory-format.md) per request and receives it in one
  * beat. Width conversion from the DRAM bus (64 bits on the ZC706 HP ports)
  * belongs to the memory system, whose bandwidth the test model charges per
  * byte. Tags let responses come back out of order.
  */
case class MemPortParams(addrBits: Int, tagBits: Int, recordBytes: Int) {
  require(addrBits >= 1 && addrBits <= 48, s"MemPortParams: addrBits must be in 1..48, got $addrBits")
  require(tagBits >= 1, s"MemPortParams: tagBits must be >= 1, got $tagBits")
  require(recordBytes >= 1, s"MemPortParams: recordBytes must be >= 1, got $recordBytes")
  val dataBits: Int = recordBytes * 8
}

class MemRequest(p: MemPortParams) extends Bundle {
  val addr = UInt(p.addrBits.W)
  val tag = UInt(p.tagBits.W)
}

/** `data` holds the record little-endian: byte 0 of the record is bits 7..0. */
class MemResponse(p: MemPortParams) extends Bundle {
  val data = UInt(p.dataBits.W)
  val tag = UInt(p.tagBits.W)
}

/** The accelerator's side of a port: it drives requests and takes responses. */
class MemPort(val p: MemPortParams) extends Bundle {
  val req = Decoupled(new MemRequest(p))
  val resp = Flipped(Decoupled(new MemResponse(p)))
}
