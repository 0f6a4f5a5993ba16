package rtaccel.sim

import scala.collection.mutable
import scala.util.Random
import rtaccel.bvh.QuantNode

/** SyntheticBvh's wide tree re-laid out as quantized nodes (layouts 4q, 8q;
  * docs/memory-format.md): a node's inner children get consecutive indices
  * and its leaves' triangles consecutive slots, in slot order (depth first,
  * as nori-bridge lays them out). The box bytes are random, except the y
  * axis: origin 0, scale 1 and lo y = the wide slot's boxMin.y (a small
  * integer), so FieldDatapath's culling distance survives the decode. The
  * x and z origins are random finite words, so the decode's FP32 add rounds
  * (it is exact only for what nori-bridge writes): the golden must round as
  * the hardware does.
  */
object SyntheticQuant {

  /** (node records as bytes, triangle records) from wide slot words (8 k ints per node). */
  def apply(
      rnd: Random,
      wide: IndexedSeq[Array[Int]],
      tris: IndexedSeq[Array[Int]],
      k: Int
  ): (IndexedSeq[Array[Byte]], IndexedSeq[Array[Int]]) = {
    val nodeBytes = QuantNode.nodeBytes(k)
    val out = mutable.ArrayBuffer.fill(1)(new Array[Byte](nodeBytes))
    val outTris = mutable.ArrayBuffer.empty[Array[Int]]
    def putInt(b: Array[Byte], at: Int, v: Int): Unit = for (j <- 0 until 4) b(at + j) = (v >>> (8 * j)).toByte
    def lay(old: Int, me: Int): Unit = {
      val w = wide(old)
      val b = out(me)
      def kind(s: Int): Int = w(8 * s) // EmptySlot, 0 (inner) or a leaf word
      val used = (0 until k).filter(s => kind(s) != rtaccel.bvh.BvhNode.EmptySlot.toInt)
      val inner = used.filter(s => kind(s) == 0)
      val childBase = out.size
      out ++= inner.map(_ => new Array[Byte](nodeBytes))
      val triBase = outTris.size
      for (s <- used if kind(s) < 0) outTris ++= (0 until (kind(s) & 0x7f)).map(i => tris(w(8 * s + 1) + i))
      putInt(b, 0, rnd.nextInt() & ~(1 << 30)); putInt(b, 4, 0); putInt(b, 8, rnd.nextInt() & ~(1 << 30))
      b(12) = (QuantNode.ExpMin + rnd.nextInt(QuantNode.ExpMax)).toByte; b(13) = 127.toByte
      b(14) = (QuantNode.ExpMin + rnd.nextInt(QuantNode.ExpMax)).toByte
      putInt(b, 16, if (inner.isEmpty) 0 else childBase)
      putInt(b, 20, triBase)
      for (s <- used) {
        b(QuantNode.FixedBytes + s) =
          (if (kind(s) == 0) QuantNode.MetaInner else QuantNode.MetaLeaf | (kind(s) & 0x7f)).toByte
        for (p <- 0 until 6) b(QuantNode.planeByte(k, p, s)) = rnd.nextInt(256).toByte
        b(QuantNode.planeByte(k, 1, s)) = java.lang.Float.intBitsToFloat(w(8 * s + 3)).toInt.toByte
      }
      for ((s, i) <- inner.zipWithIndex) lay(w(8 * s + 1), childBase + i)
    }
    lay(0, 0)
    (out.toIndexedSeq, outTris.toIndexedSeq)
  }
}
