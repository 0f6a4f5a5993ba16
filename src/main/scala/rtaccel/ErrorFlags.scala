package rtaccel

import chisel3._

/** Per-ray error bits, OR-ed in by any unit and returned with the hit. A ray
  * the hardware cannot finish correctly always comes back with one set; it
  * never comes back with a silently wrong hit.
  */
object ErrorFlags {

  /** A push found the ray's stack full: the BVH is deeper than `stackDepth`. */
  val StackOverflow = 0

  /** A node or triangle index does not fit the generated index widths. */
  val IndexOverflow = 1

  /** A leaf holds more triangles than `maxLeafSize`. */
  val LeafTooBig = 2

  /** The ray has a NaN or infinite origin/direction component, a NaN tmin or
    * tmax, or an all-zero direction, judged after narrowing to the datapath
    * format (so an origin too large for a narrow format is an error too).
    */
  val InvalidRay = 3

  /** A node box or triangle vertex word the ray met in memory is NaN or
    * infinite: the host wrote the scene wrongly. The ray never returns a
    * silent miss or hit for it.
    */
  val BadSceneData = 4

  val width = 5
  def apply(): UInt = UInt(width.W)
  def bit(i: Int): UInt = (BigInt(1) << i).U(width.W)

  /** An FP32 word that is NaN or infinite (exponent all ones). */
  def nonFinite(w: UInt): Bool = w(30, 23).andR
  def nonFiniteWord(w: Long): Boolean = ((w >> 23) & 0xff) == 0xff

  /** Names of the set bits, for reports and failing tests. */
  def describe(bits: BigInt): String =
    Seq(
      StackOverflow -> "stack-overflow",
      IndexOverflow -> "index-overflow",
      LeafTooBig -> "leaf-too-big",
      InvalidRay -> "invalid-ray",
      BadSceneData -> "bad-scene-data"
    )
      .collect { case (i, n) if bits.testBit(i) => n }.mkString("|")
}
