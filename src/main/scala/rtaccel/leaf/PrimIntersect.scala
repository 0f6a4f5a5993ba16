package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig

/** A triangle record as stored (docs/memory-format.md): nine FP32 vertex
  * coordinates, the primitive number, flags, little-endian. Records lie
  * `StrideBytes` = 64 apart; a request reads the first `RecordBytes` = 48 of
  * them (the 44 bytes of fields, rounded up to the 16-byte grain of the
  * stores and the fabric), the rest is padding.
  */
object TriangleRecord {
  val RecordBytes = 48
  val StrideBytes: Int = rtaccel.scene.MemoryImage.TriBytes
  require(StrideBytes >= RecordBytes, s"TriangleRecord: stride $StrideBytes below the $RecordBytes bytes read")
  def vertexWord(record: UInt, vertex: Int, axis: Int): UInt = {
    val w = 3 * vertex + axis
    record(32 * w + 31, 32 * w)
  }
  def prim(record: UInt): UInt = record(9 * 32 + 31, 9 * 32)
  def flags(record: UInt): UInt = record(10 * 32 + 31, 10 * 32)
}

class PrimQuery[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val ray = gen.cloneType
  val tmax = UInt(cfg.triFloat.width.W)
  val triangle = UInt((TriangleRecord.RecordBytes * 8).W)
}

/** Hit or not; t, u, v in the triangle format (u, v as in Embree:
  * point = (1-u-v) v0 + u v1 + v v2). The test includes tmin <= t <= tmax.
  */
class PrimAnswer(cfg: AccelConfig) extends Bundle {
  val hit = Bool()
  val t = UInt(cfg.triFloat.width.W)
  val u = UInt(cfg.triFloat.width.W)
  val v = UInt(cfg.triFloat.width.W)
}

/** What LeafIntersect needs of a ray/triangle unit: one query per cycle in,
  * the answer exactly `latency` cycles later, no back-pressure (II = 1).
  */
abstract class PrimIntersect[T <: Data](val cfg: AccelConfig, val gen: T) extends Module {
  def latency: Int
  val io = IO(new Bundle {
    val in = Flipped(Valid(new PrimQuery(cfg, gen)))
    val out = Valid(new PrimAnswer(cfg))
  })
}
