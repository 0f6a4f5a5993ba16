package rtaccel.study

import rtaccel.scene.{MemoryImage, Records}
import rtaccel.bvh.BvhLayout

import scala.collection.mutable

/** Orders of an image's nodes, as positions: `pos(i)` is where node i would
  * sit in the node array. Image order is the identity (nori-bridge writes
  * wide and quantized nodes breadth first, nori nodes depth first);
  * breadth-first puts the top levels first.
  */
object NodeOrder {

  /** The node indices of node i's inner children. */
  def children(img: MemoryImage, i: Long): Seq[Long] = img.layout match {
    case BvhLayout.Nori =>
      val n = Records.node(img, i).head
      if (n.isLeaf) Nil else Seq(i + 1, n.word1)
    case _ =>
      // Wide slots: word0 == 0 marks an inner child (docs/memory-format.md).
      Records.node(img, i).takeWhile(_.word0 != 0x40000000L).filter(_.word0 == 0).map(_.word1)
  }

  /** Which order the image is in: "breadth-first" when `bfs` (breadthFirst of it) is the identity,
    * "depth-first" when every node's children follow it in pre-order, else "other". */
  def name(img: MemoryImage, bfs: Array[Long]): String =
    if (bfs.indices.forall(i => bfs(i) == i)) "breadth-first"
    else if (depthFirst(img)) "depth-first"
    else "other"

  /** Pre-order: a walk that visits a node, then its children's subtrees in order, meets nodes 0, 1, 2, ... */
  def depthFirst(img: MemoryImage): Boolean = {
    var next = 0L
    val stack = mutable.Stack(0L)
    var ok = true
    while (ok && stack.nonEmpty) {
      val i = stack.pop()
      ok = i == next
      next += 1
      stack.pushAll(children(img, i).reverse)
    }
    ok && next == img.nodeCount
  }

  def breadthFirst(img: MemoryImage): Array[Long] = {
    val pos = Array.fill(img.nodeCount.toInt)(-1L)
    val queue = mutable.Queue(0L)
    var next = 0L
    while (queue.nonEmpty) {
      val i = queue.dequeue()
      require(pos(i.toInt) < 0, s"${img.source}: node $i reached twice")
      pos(i.toInt) = next
      next += 1
      queue ++= children(img, i)
    }
    require(next == img.nodeCount, s"${img.source}: ${img.nodeCount - next} nodes unreachable from the root")
    pos
  }
}
