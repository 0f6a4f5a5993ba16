package rtaccel.datapath

import rtaccel.fp.RoundingMode
import rtaccel.fp.RoundingMode.{RDN, RNE, RUP}

/** The slab test (docs/kernels.md section 3), written once for every interpretation.
  *
  * Each plane distance is computed as a magnitude product and then signed:
  * t = (b - o) * (1/d) = sign(d) * ((b - o) * |1/d|). Negation is exact and
  * RNE is sign-symmetric, so in Nearest mode this is bit for bit the spec's
  * `(b - o) * rcp` (zeros included: the sign is the XOR either way).
  *
  * == Conservative mode: why there are no false misses ==
  * Let a = bmin - o, b = bmax - o exactly, R = 1/|d| exactly, and R- <= R <= R+
  * the per-ray RTZ/RUP reciprocals. We compute
  *   Pmin = RDN(RDN(a) * (bmin < o ? R+ : R-))  <= a * R
  *   Pmax = RUP(RUP(b) * (bmax > o ? R+ : R-))  >= b * R
  * (a smaller factor of the right sign only lowers a product: case analysis
  * on the sign of the exact difference, every step monotone; RDN keeps a >= 0
  * at or above 0 and RUP keeps b <= 0 at or below it, because 0 is
  * representable). The choice is the exact difference's sign, taken from the
  * comparator the in-slab test already has, not from the rounded difference:
  * the two agree on every input (gradual underflow makes a nonzero
  * difference's rounding nonzero, of its sign; an exact zero picks R-, a NaN
  * neither side), so this is bit for bit the test on the rounded sign, and
  * the multiplier's operand mux waits on a register, not on the subtractor's
  * result (docs/fmax.md, BoxLane). For d > 0,
  * [Pmin, Pmax] encloses the exact [tmin_i, tmax_i]; for d < 0 the slab is
  * [-Pmax, -Pmin] = sign(d)[Pmax, Pmin], which encloses it too. The box is
  * narrowed outward (bmin RDN, bmax RUP), so it contains the FP32 box, and
  * every comparison after that is exact. So if the exact slab test of the
  * format's ray against the FP32 box hits, the unit hits: no false misses, in
  * any format, with no epsilon. This is the directed-rounding form of the
  * bound pbrt pads with (1 + 2 gamma(3)) (Ize, JCGT 2013): three roundings per
  * distance, each now one-sided.
  *
  * Split formats (box format narrower than the triangle format): the exact
  * ray is then the FP32 ray, not its rounding, and the ray constants are
  * bounds on it (RayKernel.outward): o <= o32 <= oHi, R- <= 1/|d32| <= R+.
  * B1 takes RDN(bmin - oHi) <= bmin - o32 and B2 RUP(bmax - o) >= bmax - o32,
  * and the argument above goes through unchanged, so the box test encloses
  * the FP32 ray's exact slab test: no false miss against the triangle unit's
  * ray. tmax comes from the triangle format rounded up ([[narrowTmax]]).
  * NaN cannot arise: R- is finite and nonzero (RTZ never overflows, and
  * 1/maxFinite >= minSubnormal when manBits >= 3), a zero difference picks R-,
  * and an infinite difference times a nonzero R is infinite.
  *
  * In Nearest mode, 0 * inf (origin on a plane, 1/d overflowed) gives a NaN
  * distance, which maximumNumber/minimumNumber drop: the interval can only widen.
  */
object BoxKernel {
  final case class Out[F, B](hit: B, near: F)

  /** The ray's tmax, kept in the triangle format `from` (the leaf unit writes
    * it), as the box lanes read it. Narrowing it (a box format narrower than
    * the triangle format) rounds UP in Conservative mode: a larger tmax only
    * keeps more boxes (`near <= tmax` is the last test of B8), so a box the
    * exact tmax would keep is never culled, and "no false misses" survives the
    * hand-over from triangle to box format. Widening is exact. Nearest mode
    * rounds to nearest, as it does every other input. Identity when the
    * formats are equal.
    */
  def narrowTmax[F, B](ar: KernelArith[F, B], rounding: BoxRounding, tmax: F, from: rtaccel.fp.FloatFormat): F =
    ar.convert(tmax, from, if (rounding == BoxRounding.Conservative) RUP else RNE)

  def apply[F, B](
      ar: KernelArith[F, B],
      rounding: BoxRounding,
      ray: RayK[F, B],
      tmax: F,
      bmin32: Seq[F],
      bmax32: Seq[F]
  ): Out[F, B] = {
    import ar._
    val cons = rounding == BoxRounding.Conservative
    def dn: RoundingMode = if (cons) RDN else RNE
    def up: RoundingMode = if (cons) RUP else RNE
    val axes = (0 until 3).map { i =>
      // o <= oHi bound the origin (split Conservative, RayKernel.outward); one value otherwise.
      val (o, oHi, d) = (ray.o(i), ray.oHi.fold(ray.o(i))(_(i)), ray.d(i))
      val bmin = fromF32(bmin32(i), dn)
      val bmax = fromF32(bmax32(i), up)
      val a = sub(bmin, oHi, dn) // B1: <= bmin - origin
      val b = sub(bmax, o, up) // B2: >= bmax - origin
      // lt(bmin, oHi) = ltZero(a) and gt(bmax, o) = gtZero(b) on every input (above); the
      // comparators are the ones `in` below uses (ge(oHi, bmin) = le(bmin, oHi), le(o, bmax)).
      val (rMin, rMax) =
        if (cons) (mux(lt(bmin, oHi), ray.rcpHi(i), ray.rcpLo(i)), mux(gt(bmax, o), ray.rcpHi(i), ray.rcpLo(i)))
        else (ray.rcpLo(i), ray.rcpLo(i))
      val pMin = mul(a, rMin, dn) // B3 (magnitude form)
      val pMax = mul(b, rMax, up) // B4
      val dNeg = signBit(d) // B5
      val flat = isZero(d) // B6
      val lo = mux(flat, negInf, mux(dNeg, neg(pMax), pMin))
      val hi = mux(flat, posInf, mux(dNeg, neg(pMin), pMax))
      val in = or(not(flat), and(ge(oHi, bmin), le(o, bmax)))
      val valid = le(bmin, bmax) // B7
      (lo, hi, and(in, valid))
    }
    // B8: a NaN lo/hi loses, so max(-inf, x) is x unless x is NaN.
    val near = axes.map(_._1).foldLeft(negInf)(max)
    val far = axes.map(_._2).foldLeft(posInf)(min)
    val hit = all(Seq(not(ray.err), all(axes.map(_._3)), le(near, far), le(ray.tmin, far), le(near, tmax)))
    Out(hit, near)
  }
}
