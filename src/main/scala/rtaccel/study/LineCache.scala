package rtaccel.study

import scala.collection.mutable

/** An LRU set-associative cache of 64-byte lines in front of the DRAM, behind the stores: a read costs the lines of
  * it that are missing. Rays are interleaved as ray IDs in flight interleave them: `inFlight` rays at a time, each
  * making one read in turn, and a finished ray's place taken by the next ray of the batch (an estimate: the real
  * interleaving depends on timing; docs/dram-traffic.md). `bytes` = 0: no cache, every line is read.
  */
final class LineCache(bytes: Long, ways: Int = 4) {
  private val sets = (bytes / (MemoryDesign.Line * ways)).toInt.max(1)
  private val lru = Array.fill(sets)(mutable.ArrayBuffer.empty[Long])

  /** Touches `line`; true if it was present. */
  def access(line: Long): Boolean = bytes > 0 && {
    val s = lru((line % sets).toInt)
    val k = s.indexOf(line)
    if (k >= 0) s.remove(k) else if (s.size == ways) s.remove(0)
    s += line
    k >= 0
  }
}

object LineCache {

  /** DRAM bytes per ray, (node, triangle), of `rays` in this order through a cache of `bytes` behind `design`'s
    * stores, `inFlight` rays interleaved. */
  def bytesPerRay(
      rays: IndexedSeq[RayReads],
      img: rtaccel.scene.MemoryImage,
      design: MemoryDesign,
      bytes: Long,
      inFlight: Int
  ): (Double, Double) = {
    val cache = new LineCache(bytes)
    var nodeB, triB = 0L
    val slots = mutable.ArrayBuffer.empty[(RayReads, Int)]
    var next = 0
    def refill(): Unit = while (slots.size < inFlight && next < rays.size) { slots += ((rays(next), 0)); next += 1 }
    refill()
    while (slots.nonEmpty) {
      var k = 0
      while (k < slots.size) {
        val (r, at) = slots(k)
        if (at >= r.reads.size) slots.remove(k)
        else {
          val read = r.reads(at)
          val missed = design.lines(img, read).count(l => !cache.access(l)) * MemoryDesign.Line
          if (design.isNode(read)) nodeB += missed else triB += missed
          slots(k) = (r, at + 1)
          k += 1
        }
      }
      refill()
    }
    (nodeB.toDouble / rays.size, triB.toDouble / rays.size)
  }
}

/** Rays reordered before a batch, as the host (librtaccel) would: by the cell of a 16 x 16 x 16 grid over the
  * batch's origins that holds the origin (Morton order), then by direction octant. Stable: ties keep their order.
  */
object RayOrder {
  val CellBits = 4

  def sorted(rays: IndexedSeq[RayReads]): IndexedSeq[RayReads] = {
    def f(b: Long) = java.lang.Float.intBitsToFloat(b.toInt).toDouble
    val origins = rays.map(_.ray.origin.map(f))
    val lo = (0 until 3).map(a => origins.map(_(a)).min)
    val hi = (0 until 3).map(a => origins.map(_(a)).max)
    val cells = 1 << CellBits
    def cell(o: Seq[Double], a: Int): Int =
      if (hi(a) <= lo(a)) 0 else ((o(a) - lo(a)) / (hi(a) - lo(a)) * cells).toInt.min(cells - 1).max(0)
    def morton(c: Seq[Int]): Int =
      (0 until CellBits).map(b => (0 until 3).map(a => ((c(a) >> b) & 1) << (3 * b + a)).sum).sum
    def octant(r: RayReads): Int = (0 until 3).map(a => if ((r.ray.dir(a) >> 31) != 0) 1 << a else 0).sum
    rays.zip(origins).sortBy { case (r, o) => (morton((0 until 3).map(cell(o, _))), octant(r)) }.map(_._1)
  }
}
