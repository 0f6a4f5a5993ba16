package rtaccel.scene

import rtaccel.fp.FloatFormat
import rtaccel.golden.RayRecord

/** The magnitudes a scene and its rays put through the intersection
  * kernels, and the exponent range a number format needs to hold them.
  *
  * @param maxAbs       largest |coordinate| of any vertex (scene.json extent) or ray origin
  * @param smallestEdge shortest triangle edge (scene.json), > 0
  * @param dirMin       smallest, over rays, of the ray's largest |direction component|
  * @param dirMax       largest |direction component| of any ray
  */
final case class NumericRange(maxAbs: Double, smallestEdge: Double, dirMin: Double, dirMax: Double) {

  /** D: every vertex-minus-origin component is at most 2 maxAbs. */
  def span: Double = 2 * maxAbs

  /** Largest intermediate of either triangle kernel (docs/kernels.md, bounds in the kernel's order):
    *  - watertight: sheared x/y differences <= 2D (|Sx|, |Sy| <= 1 since kz is the largest direction
    *    component), edge functions U, V, W <= 2 (2D)^2 = 8 D^2, det <= 24 D^2, scaled z <= D / dirMin,
    *    so T = U Az + V Bz + W Cz <= 24 D^3 / dirMin;
    *  - Moller-Trumbore: pvec = d x e2 <= 2 dirMax D, det <= 6 dirMax D^2, qvec <= 2 D^2, t numerator <= 6 D^3.
    * The box kernel's (b - o) / d may overflow to infinity only for near-axis-parallel rays, where
    * infinity orders the slab exactly as the huge finite value would: not a constraint.
    */
  def largestIntermediate: Double =
    Seq(24 * math.pow(span, 3) / dirMin.min(1.0), 6 * math.pow(span, 3) * dirMax.max(1.0), 6 * dirMax * span * span).max

  /** Smallest quantity that must stay normal: a ray passing near a triangle of edge s gives edge
    * functions and det of order s^2; below the smallest normal they lose precision (gradual underflow).
    */
  def smallestIntermediate: Double = smallestEdge * smallestEdge

  /** Unbiased exponents the format must reach: its emax above log2(largest) (with one binade of
    * margin for the rounding of the sums) and its emin at or below log2(smallest).
    */
  def neededEmax: Int = math.ceil(log2(largestIntermediate)).toInt + 1
  def neededEmin: Int = math.floor(log2(smallestIntermediate)).toInt

  /** Fewest exponent bits (at least 3) whose emax and emin cover the range. */
  def expBits: Int =
    Iterator.from(3).find(e => FloatFormat(e, 2).emax >= neededEmax && FloatFormat(e, 2).emin <= neededEmin).get

  /** Stored mantissa bits that keep the shortest edge at least two units in the last place at the
    * largest coordinate: with fewer, rounding the FP32 inputs into the format can merge a
    * triangle's vertices (zero area, rejected by rule) or move them enough to change which
    * triangle a ray meets first. The sweep's hard cases show exactly this below the bound
    * (docs/reports/speed-vs-error.md); it is reported, not enforced, since a few collapsed slivers
    * may be acceptable in an image.
    */
  def neededManBits: Int = math.max(2, math.ceil(log2(maxAbs.max(smallestEdge) / smallestEdge)).toInt + 1)

  /** Why `fmt` cannot hold this range, if it cannot. */
  def misfit(fmt: FloatFormat): Option[String] =
    Option.when(fmt.emax < neededEmax || fmt.emin > neededEmin)(
      f"coordinates up to $maxAbs%.4g and edges down to $smallestEdge%.3g need exponents $neededEmin..$neededEmax " +
        s"(${expBits} exponent bits); ${fmt.name} reaches ${fmt.emin}..${fmt.emax}, so kernel intermediates would overflow or underflow"
    )

  private def log2(x: Double) = math.log(x.max(Double.MinPositiveValue)) / math.log(2)
}

object NumericRange {
  def apply(extentAbs: Double, smallestEdge: Double, rays: Seq[RayRecord]): NumericRange = {
    def f(b: Long) = math.abs(FloatText.fromBits(b).toDouble)
    val finite = rays.filter(r => (r.origin ++ r.dir).forall(b => !f(b).isNaN && !f(b).isInfinite))
    val origins = finite.flatMap(_.origin.map(f))
    val dirMax = finite.map(_.dir.map(f).max)
    NumericRange(
      maxAbs = (extentAbs +: origins).max,
      smallestEdge = if (smallestEdge > 0 && !smallestEdge.isInfinite) smallestEdge else 1.0,
      dirMin = if (dirMax.isEmpty) 1.0 else dirMax.min.max(Double.MinPositiveValue),
      dirMax = if (dirMax.isEmpty) 1.0 else dirMax.max
    )
  }
}
