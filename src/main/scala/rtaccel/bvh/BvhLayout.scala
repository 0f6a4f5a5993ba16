package rtaccel.bvh

/** How BVH nodes are laid out in memory (docs/memory-format.md, version 2),
  * and so how many child boxes BboxIntersect tests per node.
  *
  *  - [[BvhLayout.Nori]]: today's 32-byte binary node holding its own box
  *    (Nori's layout; left child implicit): one box per node fetch.
  *  - [[BvhLayout.Wide]]`(k)`: a node of k 32-byte child slots, each with the
  *    child's box, so one fetch brings k boxes and BboxIntersect tests all of
  *    them at once (k lanes).
  *  - `Wide(k, quantized = true)` (`4q`, `8q`): the same k slots, but the
  *    node stores its child boxes as 8-bit offsets from a per-node origin and
  *    power-of-two scale (docs/memory-format.md, "Quantized wide node"),
  *    64 bytes (k = 4) or 80 bytes (k = 8). BvhNode.decode turns it into the
  *    same k slots (exact FP32 boxes), so everything after the decoder is
  *    the wide layout's.
  */
sealed trait BvhLayout {

  /** The image header's `layout` word. */
  def code: Int

  /** Boxes per node record: the box lanes of BboxIntersect. */
  def lanes: Int

  /** Bytes of one node record: one memory request. */
  def nodeBytes: Int = 32 * lanes

  /** Most stack pushes one decision makes. */
  def maxPushes: Int

  /** What `make regress BVH=` and `nori-bridge compile --bvh` call it. */
  def name: String

  /** Child boxes stored quantized (4q, 8q). */
  def quantized: Boolean
}

object BvhLayout {
  case object Nori extends BvhLayout {
    val code = 0
    val lanes = 1
    val maxPushes = 1
    val name = "nori"
    val quantized = false
  }
  final case class Wide(k: Int, quantized: Boolean = false) extends BvhLayout {
    require(Seq(2, 4, 8).contains(k), s"BvhLayout.Wide: k must be 2, 4 or 8, got $k")
    require(!quantized || k >= 4, s"BvhLayout.Wide: quantized nodes are 4- or 8-wide, got $k")
    def code: Int = if (quantized) 16 + k else k
    def lanes: Int = k

    /** Quantized: 24 fixed bytes + 7 per slot, padded to a multiple of 16 (64, 80). */
    override def nodeBytes: Int = if (quantized) (24 + 7 * k + 15) / 16 * 16 else 32 * k
    def maxPushes: Int = k - 1
    def name: String = if (quantized) s"${k}q" else k.toString
  }

  val all: Seq[BvhLayout] = Seq(Nori, Wide(2), Wide(4), Wide(8), Wide(4, quantized = true), Wide(8, quantized = true))

  def parse(s: String): BvhLayout = all.find(_.name == s.trim)
    .getOrElse(throw new IllegalArgumentException(
      s"BVH layout '$s': expected one of ${all.map(_.name).mkString(", ")}"
    ))

  /** From an image header's `layout` word; `source` names the file for the error. */
  def fromCode(code: Long, source: String): BvhLayout = all.find(_.code == code)
    .getOrElse(throw new IllegalArgumentException(
      s"$source: header layout = $code, expected 0 (nori), 2, 4, 8, 20 (4q) or 24 (8q)"
    ))
}
