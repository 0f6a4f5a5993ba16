package rtaccel

import chisel3._
import chisel3.util._

/** A decoded 32-byte BVH node (docs/memory-format.md, version 1):
  * word0 bit 31 = leaf, bits 30..0 = leaf triangle count or inner split axis;
  * word1 = first triangle (leaf) or right child (inner); then six FP32 bounds.
  * Bounds stay raw FP32 bits here; BboxIntersect narrows them to its format.
  */
class BvhNode(cfg: AccelConfig) extends Bundle {
  val links  = new NodeLinks(cfg)
  val boxMin = Vec(3, UInt(32.W))
  val boxMax = Vec(3, UInt(32.W))
}

/** The part of a node that steers traversal, without its box. */
class NodeLinks(cfg: AccelConfig) extends Bundle {
  val isLeaf     = Bool()
  val axis       = UInt(2.W)
  val rightChild = UInt(cfg.nodeIndexBits.W)
  val first      = UInt(cfg.triIndexBits.W)
  val count      = UInt(cfg.leafCountBits.W)
  /** The record does not fit this hardware: see ErrorFlags. */
  val errors     = ErrorFlags()
}

object BvhNode {
  val RecordBytes = 32

  /** Decodes a little-endian record, flagging fields too wide for `cfg`. */
  def decode(cfg: AccelConfig, record: UInt): BvhNode = {
    require(record.getWidth == RecordBytes * 8, s"BvhNode.decode: record must be ${RecordBytes * 8} bits")
    def word(i: Int): UInt = record(32 * i + 31, 32 * i)
    val w0 = word(0)
    val w1 = word(1)
    val n = Wire(new BvhNode(cfg))
    val l = n.links
    l.isLeaf     := w0(31)
    l.axis       := w0(1, 0)
    l.rightChild := w1(cfg.nodeIndexBits - 1, 0)
    l.first      := w1(cfg.triIndexBits - 1, 0)
    l.count      := w0(cfg.leafCountBits - 1, 0)
    for (a <- 0 until 3) {
      n.boxMin(a) := word(2 + a)
      n.boxMax(a) := word(5 + a)
    }
    def highBitsSet(w: UInt, keep: Int): Bool = if (keep >= 32) false.B else w(31, keep).orR
    val indexTooWide = Mux(w0(31), highBitsSet(w1, cfg.triIndexBits), highBitsSet(w1, cfg.nodeIndexBits))
    val leafTooBig   = w0(31) && (w0(30, 0) > cfg.maxLeafSize.U)
    // An inner node's axis must be 0, 1 or 2; anything else is a corrupt image.
    val badAxis      = !w0(31) && (w0(30, 0) > 2.U)
    l.errors := Mux(indexTooWide || badAxis, ErrorFlags.bit(ErrorFlags.IndexOverflow), 0.U) |
      Mux(leafTooBig, ErrorFlags.bit(ErrorFlags.LeafTooBig), 0.U)
    n
  }
}
