package rtaccel.system

import rtaccel.scene.MemoryImage

import java.nio.{ByteBuffer, ByteOrder}
import scala.collection.mutable
import scala.util.Random

/** A random BVH in the real memory format (depth-first, left child = index
  * + 1), for control-path tests with FieldDatapath: box words carry hash
  * inputs and a culling distance, triangle words carry t/u/v and a hit key.
  */
object SyntheticBvh {
  private def f(x: Float): Int = java.lang.Float.floatToRawIntBits(x)

  def apply(rnd: Random, maxDepth: Int, maxLeaf: Int, leafChance: Double = 0.3): MemoryImage = {
    val nodes = mutable.ArrayBuffer.empty[Array[Int]]
    val tris  = mutable.ArrayBuffer.empty[Array[Int]]
    var depthSeen = 0
    def box(n: Array[Int]): Unit = {
      n(2) = rnd.nextInt()
      n(3) = f(rnd.nextInt(9).toFloat) // culled once the ray has a hit closer than this
      for (k <- 4 until 8) n(k) = rnd.nextInt()
    }
    def build(depth: Int): Unit = {
      depthSeen = depthSeen.max(depth)
      val n = new Array[Int](8)
      nodes += n
      box(n)
      if (depth >= maxDepth || (depth > 0 && rnd.nextDouble() < leafChance)) {
        val count = rnd.nextInt(maxLeaf + 1)
        n(0) = (1 << 31) | count
        n(1) = tris.size
        for (_ <- 0 until count) {
          val t = Array.fill(12)(0)
          t(0) = f((1 + rnd.nextInt(8)).toFloat); t(1) = rnd.nextInt(); t(2) = rnd.nextInt(); t(3) = rnd.nextInt()
          tris += t
        }
      } else {
        n(0) = rnd.nextInt(3)
        build(depth + 1)
        n(1) = nodes.size
        build(depth + 1)
      }
    }
    build(0)
    // prim: each triangle's number in a scrambled (but unique) order.
    val order = rnd.shuffle(tris.indices.toList)
    for ((t, p) <- tris.zip(order)) t(9) = p

    def align64(x: Int) = (x + 63) / 64 * 64
    val nodeOffset = MemoryImage.HeaderBytes
    val triOffset  = align64(nodeOffset + nodes.size * 32)
    val buf = ByteBuffer.allocate(triOffset + tris.size * 48).order(ByteOrder.LITTLE_ENDIAN)
    buf.put(MemoryImage.Magic)
    Seq(MemoryImage.Version.toInt, nodes.size, tris.size, nodeOffset, triOffset, 32, 48, maxLeaf, depthSeen).foreach(buf.putInt)
    buf.position(nodeOffset); nodes.foreach(_.foreach(buf.putInt))
    buf.position(triOffset); tris.foreach(_.foreach(buf.putInt))
    MemoryImage.fromBytes(s"synthetic BVH (depth <= $maxDepth)", buf.array())
  }
}
