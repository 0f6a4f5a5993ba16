package rtaccel.study

import rtaccel.bvh.BvhLayout
import rtaccel.scene.{MemoryImage, Records}

import scala.collection.mutable

/** Treelet ray queues (Aila & Karras, HPG 2010), on paper. The nodes past the node store are cut into treelets of
  * at most `treeletBytes` (nodes with their leaves' triangles, grown breadth first from a root; what does not fit
  * starts a new treelet), each assumed stored contiguously (nori-bridge would write the image treelet by treelet).
  * Triangles of leaves whose node is in the store form treelets of their own, `treeletBytes` of the triangle array
  * each. A ray's reads past the stores become a list of treelet visits. The scheduler runs in rounds: it takes the
  * treelets in id order (parents before children), and for each one with rays queued either streams the whole
  * treelet on chip once and runs those rays through it, or, when that costs less, lets the rays read their own lines
  * (a hybrid: the treelet's bytes against the queued rays' own). A ray that moves on to a later treelet is queued
  * for it in the same round; one that goes back up (a pop into an earlier treelet) waits for the next round.
  * Every change of treelet parks the ray once.
  */
object Treelets {
  final case class Result(bytesPerRay: Double, parksPerRay: Double, loads: Int, treelets: Int)

  /** For node i, its inner children and its leaf slots (first triangle, count). */
  private def slots(img: MemoryImage, i: Long): (Seq[Long], Seq[(Long, Int)]) = {
    val recs = Records.node(img, i)
    img.layout match {
      case BvhLayout.Nori => throw new IllegalArgumentException(s"${img.source}: the treelet study takes wide layouts")
      case _ =>
        val live = recs.filter(_.word0 != rtaccel.bvh.BvhNode.EmptySlot)
        (live.filter(r => !r.isLeaf).map(_.word1), live.filter(_.isLeaf).map(r => (r.word1, r.low31.toInt)))
    }
  }

  def run(img: MemoryImage, design: MemoryDesign, rays: IndexedSeq[RayReads], treeletBytes: Long): Result = {
    val nb = img.nodeBytes
    val rb = design.tris.recordBytes.toLong
    val n = img.nodeCount.toInt
    val inStore = (i: Long) => (i + 1) * nb <= design.nodeStoreBytes
    val triInStore = (j: Long) => (j + 1) * rb <= design.triStoreBytes
    val info = Array.tabulate(n)(i => slots(img, i.toLong))
    val nodeT = Array.fill(n)(-1)
    val triT = Array.fill(img.triCount.toInt)(-1)
    val size = mutable.ArrayBuffer.empty[Long]
    def leafBytes(i: Int) = info(i)._2.map { case (f, c) => (f until f + c).count(j => !triInStore(j)) * rb }.sum
    // Roots: nodes past the store whose parent is in it (breadth-first image: the store is a prefix).
    val roots = mutable.Queue.empty[Int]
    for (i <- 0 until n if inStore(i)) info(i)._1.filterNot(inStore).foreach(c => roots += c.toInt)
    if (!inStore(0)) roots += 0
    while (roots.nonEmpty) {
      val t = size.size
      var bytes = 0L
      val q = mutable.Queue(roots.dequeue())
      while (q.nonEmpty) {
        val i = q.dequeue()
        val b = nb + leafBytes(i)
        if (bytes > 0 && bytes + b > treeletBytes) roots += i
        else { bytes += b; nodeT(i) = t; q ++= info(i)._1.map(_.toInt) }
      }
      size += bytes
    }
    for (i <- 0 until n if nodeT(i) >= 0; (f, c) <- info(i)._2; j <- f until f + c) triT(j.toInt) = nodeT(i)
    // Leaves of stored nodes: their triangles past the triangle store, in runs of treeletBytes of the array.
    val firstChunk = size.size
    val chunkTris = (treeletBytes / rb).max(1)
    for (i <- 0 until n if inStore(i); (f, c) <- info(i)._2; j <- f until f + c if !triInStore(j)) {
      val t = firstChunk + (j / chunkTris).toInt
      while (size.size <= t) size += 0L
      size(t) += rb
      triT(j.toInt) = t
    }
    val loadBytes = size.map(b => MemoryDesign.Line * ((b + MemoryDesign.Line - 1) / MemoryDesign.Line))

    // Each ray's visits: (treelet, its own DRAM bytes there), consecutive reads of one treelet merged.
    val visits: IndexedSeq[Array[(Int, Long)]] = rays.map { r =>
      val v = mutable.ArrayBuffer.empty[(Int, Long)]
      for (read <- r.reads) {
        val own = design.bytes(img, read)
        if (own > 0) {
          val t = read match {
            case NodeRead(i)    => nodeT(i.toInt)
            case TriRead(j)     => triT(j.toInt)
            case LeafRead(f, _) => triT(f.toInt)
          }
          require(t >= 0, s"${img.source}: a read past the stores has no treelet ($read)")
          if (v.nonEmpty && v.last._1 == t) v(v.size - 1) = (t, v.last._2 + own) else v += ((t, own))
        }
      }
      v.toArray
    }
    val at = Array.fill(rays.size)(0)
    var now = mutable.TreeMap.empty[Int, mutable.ArrayBuffer[Int]]
    def queue(m: mutable.TreeMap[Int, mutable.ArrayBuffer[Int]], t: Int, r: Int) =
      m.getOrElseUpdate(t, mutable.ArrayBuffer.empty) += r
    for (r <- rays.indices if visits(r).nonEmpty) queue(now, visits(r)(0)._1, r)
    var bytes, parks = 0L
    var loads = 0
    while (now.nonEmpty) {
      val later = mutable.TreeMap.empty[Int, mutable.ArrayBuffer[Int]]
      while (now.nonEmpty) {
        val (t, rs) = now.head
        now -= t
        val own = rs.map(r => visits(r)(at(r))._2).sum
        if (loadBytes(t) < own) { bytes += loadBytes(t); loads += 1 }
        else bytes += own
        for (r <- rs) {
          at(r) += 1
          if (at(r) < visits(r).length) {
            parks += 1
            val u = visits(r)(at(r))._1
            queue(if (u > t) now else later, u, r)
          }
        }
      }
      now = later
    }
    Result(bytes.toDouble / rays.size, parks.toDouble / rays.size, loads, size.size)
  }
}
