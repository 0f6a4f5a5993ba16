package rtaccel.study

import rtaccel.scene.MemoryImage

/** One candidate of the study, named by `key` on the command line (`--only`): a node layout (which compiled image it
  * reads), a memory design and how reads past the stores reach DRAM.
  */
final case class Candidate(
    key: String,
    name: String,
    layout: String,
    design: MemoryDesign,
    path: Candidate.Path = Candidate.Direct
) {
  def bram(cores: Int, batch: Int): Int = design.storeBram(cores) + (path match {
    case Candidate.Direct => 0
    case Candidate.Cached(bytes, _) =>
      MemoryDesign.copies(cores) * (MemoryDesign.bram(bytes) + Candidate.tagBram(bytes))
    // Two treelet buffers (one streaming in while the other is traced), copied as the stores are; queues on chip
    // hold the batch's parked ray states.
    case Candidate.TreeletQueues(bytes, inDram) =>
      MemoryDesign.copies(cores) * 2 * MemoryDesign.bram(bytes) +
        (if (inDram) 0 else MemoryDesign.bram(batch.toLong * Candidate.ParkBytes))
  })
}

object Candidate {
  sealed trait Path

  /** Every read past the stores goes to DRAM, in any order: bytes per ray do not depend on the rays' order. */
  case object Direct extends Path

  /** Through an LRU cache of `bytes`, rays in batch order or reordered (RayOrder). */
  final case class Cached(bytes: Long, reorder: Boolean) extends Path

  /** Treelet ray queues (Treelets), treelets of at most `bytes`; parked ray states in DRAM or on chip. */
  final case class TreeletQueues(bytes: Long, inDram: Boolean) extends Path

  /** A parked ray's state, an estimate: the 48-byte ray, its best hit so far (t, prim: 8 bytes), the node to resume
    * (4) and up to 8 stack entries of 8 bytes, in two 64-byte lines. In DRAM a park costs a write and a read. */
  val ParkBytes = 128L

  /** Tags of a 4-way cache of 64-byte lines: about 20 bits a line (an estimate), 36 Kbit per BRAM36. */
  def tagBram(bytes: Long): Int = math.ceil(bytes / 64.0 * 20 / 36864).toInt
}

/** DRAM bytes per ray of one candidate on one ray set, by region, at 1, 2 and 4 cores. */
final case class Traffic(
    nodes: Seq[Double],
    tris: Seq[Double],
    rays: Double,
    hits: Double,
    parks: Double,
    park: Double
) {
  def total(k: Int): Double = nodes(k) + tris(k) + rays + hits + park

  /** Bytes read by m_axi (R channel): everything but the hits and the parks' writes. */
  def readBytes(k: Int): Double = nodes(k) + tris(k) + rays + park / 2
}

object Traffic {
  val Cores: Seq[Int] = Seq(1, 2, 4)

  /** Ray IDs per core: the rays in flight that a cache sees interleaved, the ZC706 configuration's. */
  val IdsPerCore: Int = rtaccel.AccelConfig.zc706.numRayIds

  def of(c: Candidate, img: MemoryImage, rays: IndexedSeq[RayReads]): Traffic = {
    val hits = c.design.hitBytes.toDouble
    val rayBytes = rtaccel.system.SystemConfig.RayBytes.toDouble
    c.path match {
      case Candidate.Direct =>
        val (n, t) = rays.flatMap(_.reads).partition(c.design.isNode)
        val nb = n.map(c.design.bytes(img, _)).sum.toDouble / rays.size
        val tb = t.map(c.design.bytes(img, _)).sum.toDouble / rays.size
        Traffic(Cores.map(_ => nb), Cores.map(_ => tb), rayBytes, hits, 0, 0)
      case Candidate.Cached(bytes, reorder) =>
        val order = if (reorder) RayOrder.sorted(rays) else rays
        val per = Cores.map(k => LineCache.bytesPerRay(order, img, c.design, bytes, IdsPerCore * k))
        Traffic(per.map(_._1), per.map(_._2), rayBytes, hits, 0, 0)
      case Candidate.TreeletQueues(bytes, inDram) =>
        val r = Treelets.run(img, c.design, rays, bytes)
        // Node and triangle bytes are not told apart here: the treelet loads carry both (shown under nodes).
        Traffic(
          Cores.map(_ => r.bytesPerRay),
          Cores.map(_ => 0.0),
          rayBytes,
          hits,
          r.parksPerRay,
          if (inDram) r.parksPerRay * 2 * Candidate.ParkBytes else 0
        )
    }
  }
}
