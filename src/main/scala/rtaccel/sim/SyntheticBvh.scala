package rtaccel.sim

import rtaccel.scene.MemoryImage
import rtaccel.bvh.BvhLayout

import java.nio.{ByteBuffer, ByteOrder}
import scala.collection.mutable
import scala.util.Random

/** A random BVH in the real memory format of a layout (docs/memory-format.md),
  * for control-path tests with FieldDatapath: box words carry hash inputs and
  * a culling distance (word 3 = boxMin.y, a small float, also the entry
  * distance that orders a wide node's children, so ties are common), triangle
  * words carry t/u/v and a hit key.
  *
  *  - nori: depth-first, left child = index + 1, right child stored.
  *  - wide: nodes of K slots, 1..K used (the rest empty), each a leaf (0..maxLeaf
  *    triangles) or an inner child.
  *  - quantized wide (4q, 8q): the wide tree re-laid out by SyntheticQuant.
  * The header's bvhDepth is the layout's stack bound, computed as documented.
  */
object SyntheticBvh {
  private def f(x: Float): Int = java.lang.Float.floatToRawIntBits(x)

  /** A random word that is a finite FP32 value (exponent bit 30 clear): scene data is never NaN or infinite. */
  private def finite(w: Int): Int = w & ~(1 << 30)

  def apply(
      rnd: Random,
      maxDepth: Int,
      maxLeaf: Int,
      leafChance: Double = 0.3,
      layout: BvhLayout = BvhLayout.Nori
  ): MemoryImage = {
    val nodes = mutable.ArrayBuffer.empty[Array[Int]]
    val tris = mutable.ArrayBuffer.empty[Array[Int]]
    val k = layout.lanes
    def box(n: Array[Int], at: Int): Unit = {
      n(at + 2) = finite(rnd.nextInt())
      n(at + 3) = f(rnd.nextInt(9).toFloat) // culled once the ray has a hit closer than this
      for (i <- 4 until 8) n(at + i) = finite(rnd.nextInt())
    }
    def leafTris(): (Int, Int) = {
      val count = rnd.nextInt(maxLeaf + 1)
      val first = tris.size
      for (_ <- 0 until count) {
        val t = Array.fill(12)(0)
        t(0) = f((1 + rnd.nextInt(8)).toFloat); t(1) = finite(rnd.nextInt()); t(2) = finite(rnd.nextInt());
        t(3) = finite(rnd.nextInt())
        tris += t
      }
      ((1 << 31) | count, first)
    }
    // Returns the stack bound of the subtree (sum of used slots - 1 along the worst path).
    def buildNori(depth: Int): Int = {
      val n = new Array[Int](8)
      nodes += n
      box(n, 0)
      if (depth >= maxDepth || (depth > 0 && rnd.nextDouble() < leafChance)) {
        val (w0, w1) = leafTris(); n(0) = w0; n(1) = w1
        0
      } else {
        n(0) = rnd.nextInt(3)
        val l = buildNori(depth + 1)
        n(1) = nodes.size
        1 + l.max(buildNori(depth + 1))
      }
    }
    def buildWide(depth: Int): Int = {
      val n = new Array[Int](8 * k)
      nodes += n
      val used = if (depth == 0) 1 + rnd.nextInt(k) else 2 + rnd.nextInt(k - 1)
      var deepest = 0
      for (s <- 0 until k) {
        if (s >= used) n(8 * s) = rtaccel.bvh.BvhNode.EmptySlot.toInt // empty: word0 marks it, the rest stays zero
        else {
          box(n, 8 * s)
          if (depth + 1 >= maxDepth || rnd.nextDouble() < leafChance) {
            val (w0, w1) = leafTris(); n(8 * s) = w0; n(8 * s + 1) = w1
          } else {
            n(8 * s) = 0
            n(8 * s + 1) = nodes.size
            deepest = deepest.max(buildWide(depth + 1))
          }
        }
      }
      used - 1 + deepest
    }
    val stackBound = if (layout == BvhLayout.Nori) buildNori(0) else buildWide(0)
    // prim: each triangle's number in a scrambled (but unique) order.
    val order = rnd.shuffle(tris.indices.toList)
    for ((t, p) <- tris.zip(order)) t(9) = p

    // Quantized: the same tree, re-laid out (SyntheticQuant).
    val (quantNodes, outTris) = layout match {
      case w: BvhLayout.Wide if w.quantized =>
        val (q, t) = SyntheticQuant(rnd, nodes.toIndexedSeq, tris.toIndexedSeq, k); (Some(q), t)
      case _ => (None, tris.toIndexedSeq)
    }
    def align64(x: Int) = (x + 63) / 64 * 64
    val nodeOffset = MemoryImage.HeaderBytes
    val triOffset = align64(nodeOffset + nodes.size * layout.nodeBytes)
    val buf = ByteBuffer.allocate(triOffset + tris.size * MemoryImage.TriBytes).order(ByteOrder.LITTLE_ENDIAN)
    buf.put(MemoryImage.Magic)
    Seq(
      MemoryImage.Version.toInt,
      nodes.size,
      tris.size,
      nodeOffset,
      triOffset,
      layout.nodeBytes,
      MemoryImage.TriBytes,
      maxLeaf,
      stackBound,
      layout.code
    ).foreach(buf.putInt)
    buf.position(nodeOffset)
    quantNodes match {
      case Some(q) => q.foreach(b => buf.put(b))
      case None    => nodes.foreach(_.foreach(buf.putInt))
    }
    for ((t, i) <- outTris.zipWithIndex) { buf.position(triOffset + MemoryImage.TriBytes * i); t.foreach(buf.putInt) }
    MemoryImage.fromBytes(s"synthetic ${layout.name} BVH (depth <= $maxDepth)", buf.array())
  }

  /** `img` with NaN or infinite words written over a share of its used node
    * slots' boxes and its triangles' vertices (at least one of each), as a
    * host that wrote the scene wrongly would leave it. Returns the image and
    * how many box and vertex words were hit.
    */
  def corrupt(img: MemoryImage, rnd: Random, share: Double): (MemoryImage, Int, Int) = {
    val bytes = img.bytes.clone()
    val buf = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    val bad = Seq(0x7fc00000, 0xffc00001, 0x7f800000, 0xff800000) // quiet NaN, NaN, +inf, -inf
    val slots = for (
      i <- 0L until img.nodeCount; s <- 0 until img.layout.lanes
      if buf.getInt((img.nodeAddr(i) + 32 * s).toInt) != rtaccel.bvh.BvhNode.EmptySlot.toInt
    ) yield (img.nodeAddr(i) + 32 * s).toInt
    val boxes = slots.filter(_ => rnd.nextDouble() < share) :+ slots(rnd.nextInt(slots.size))
    for (at <- boxes) buf.putInt(at + 8 + 4 * rnd.nextInt(6), bad(rnd.nextInt(4)))
    require(img.triCount > 0, s"${img.source}: no triangles to corrupt")
    val tris = (0L until img.triCount).filter(_ => rnd.nextDouble() < share) :+ rnd.nextInt(img.triCount.toInt).toLong
    // Vertex words 4..8: FieldDatapath's arithmetic reads only words 0..3, so only the flag can tell.
    for (j <- tris) buf.putInt((img.triAddr(j) + 4 * (4 + rnd.nextInt(5))).toInt, bad(rnd.nextInt(4)))
    (MemoryImage.fromBytes(s"${img.source} with bad words", bytes), boxes.size, tris.size)
  }
}
