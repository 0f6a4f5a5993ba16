package rtaccel.datapath

import rtaccel.fp.RoundingMode.{RDN, RNE, RUP, RTZ}

/** Watertight shear constants (docs/kernels.md R2-R5): one-hot axes and Sx, Sy, Sz. */
final case class Shear[F, B](kx: Seq[B], ky: Seq[B], kz: Seq[B], sx: F, sy: F, sz: F)

/** A ray's per-ray constants in the datapath format, under any interpretation.
  *
  * @param rcpLo |1/d[i]| rounded toward zero (Conservative) or to nearest (Nearest)
  * @param rcpHi |1/d[i]| rounded away from zero (Conservative); `rcpLo` in Nearest mode
  * @param err   the error bit R6, evaluated on the format's values
  * @param oHi   the box lanes' upper origin bound when `o` is a lower one (split formats,
  *              Conservative: the FP32 origin narrowed down and up); None: `o` is the origin
  */
final case class RayK[F, B](
    o: Seq[F],
    d: Seq[F],
    tmin: F,
    err: B,
    rcpLo: Seq[F],
    rcpHi: Seq[F],
    shear: Option[Shear[F, B]],
    oHi: Option[Seq[F]] = None
)

/** A ray's constants for both units: `box` in the box format, `tri` in the
  * triangle format. With one format for both they are the same object (one
  * setup, shared). Split, each side is set up in its own format from the FP32
  * ray (docs/kernels.md section 2, "Split formats"): `box` carries no shear,
  * `tri` no reciprocals (empty `rcpLo`/`rcpHi`).
  */
final case class SplitRay[F, B](box: RayK[F, B], tri: RayK[F, B]) {
  def shared: Boolean = box eq tri
}

/** Per-ray setup (docs/kernels.md section 2), written once for every interpretation. */
object RayKernel {

  /** The constants of both units and the ray's tmax in the triangle format.
    * With `boxAr.fmt == triAr.fmt` this is [[apply]], shared. Otherwise each
    * side narrows the FP32 ray itself, with the same rules as [[apply]]: the
    * ray the box lanes trace is the box format's rounding of the FP32 ray,
    * the triangle unit's the triangle format's; neither is derived from the
    * other, so each unit's guarantee (conservative boxes, watertight
    * triangles) holds relative to the ray it is given. The error bit is either
    * side's (a ray one unit cannot trace is flagged).
    */
  def split[F, B](
      boxAr: KernelArith[F, B],
      triAr: KernelArith[F, B],
      o32: Seq[F],
      d32: Seq[F],
      tmin32: F,
      tmax32: F,
      rounding: BoxRounding,
      test: TriangleTest
  ): (SplitRay[F, B], F, B) =
    if (boxAr.fmt == triAr.fmt) {
      val (k, tmax) = apply(triAr, o32, d32, tmin32, tmax32, rounding, test)
      (SplitRay(k, k), tmax, k.err)
    } else {
      val box = if (rounding == BoxRounding.Conservative) outward(boxAr, o32, d32, tmin32, tmax32)
      else narrowed(boxAr, o32, d32, tmin32, tmax32, rounding, withRcp = true, withNearest = false)._1
      val (tri, tmax, _) = narrowed(triAr, o32, d32, tmin32, tmax32, rounding, withRcp = false, withNearest = false)
      // R4 without the box's reciprocals: 1/d[kz] (RNE) on its own, the same bits as -(1/|d|) picked by sign.
      val shear = Option.when(test == TriangleTest.Watertight)(shearOf(triAr, tri.d, tri.d.map(triAr.abs), None))
      (SplitRay(box, tri.copy(shear = shear)), tmax, boxAr.or(box.err, tri.err))
    }

  /** The ray's constants and its tmax, from FP32 inputs.
    *
    * Narrowing: o and d round to nearest (this is the ray the datapath traces;
    * the conservative guarantee is relative to it). In Conservative mode tmin
    * rounds down and tmax up, which only widens [tmin, tmax].
    * Errors are judged on the narrowed values: an origin that overflows the
    * format, or a direction that underflows to zero, cannot be traced in it.
    */
  def apply[F, B](
      ar: KernelArith[F, B],
      o32: Seq[F],
      d32: Seq[F],
      tmin32: F,
      tmax32: F,
      rounding: BoxRounding,
      test: TriangleTest
  ): (RayK[F, B], F) = {
    val watertight = test == TriangleTest.Watertight
    val (k, tmax, rcpNearest) = narrowed(ar, o32, d32, tmin32, tmax32, rounding, withRcp = true, watertight)
    val shear = Option.when(watertight)(shearOf(ar, k.d, k.d.map(ar.abs), Some(rcpNearest)))
    (k.copy(shear = shear), tmax)
  }

  /** The box lanes' constants of a split, Conservative datapath: bounds on the
    * FP32 ray itself, not a rounding of it, so that the box test is
    * conservative for the ray the (wider) triangle unit traces:
    *  - origin: `o` = RDN(o32) <= o32 <= RUP(o32) = `oHi` (BoxKernel subtracts
    *    the bound that makes each difference a bound: bmin - oHi, bmax - o);
    *  - direction: `d` is d32 rounded away from zero (RUP if positive, RDN if
    *    negative), so it is zero exactly when d32 is (the flat-axis test B6 is
    *    FP32's) and has d32's sign (dirNeg);
    *  - rcpLo = RTZ(1/|d away|) <= 1/|d32| <= RUP(1/|RTZ(d32)|) = rcpHi (a
    *    d32 that underflows to 0 gives rcpHi = inf, still an upper bound);
    *  - tmin RDN, tmax RUP, as in [[apply]].
    * The error bit is R6 on these values: an origin whose bounds leave the
    * format, or a direction whose magnitude overflows it, is flagged.
    */
  private def outward[F, B](ar: KernelArith[F, B], o32: Seq[F], d32: Seq[F], tmin32: F, tmax32: F): RayK[F, B] = {
    import ar._
    val oLo = o32.map(fromF32(_, RDN))
    val oHi = o32.map(fromF32(_, RUP))
    // The sign is read from the narrowed RTZ value (a zero keeps its sign):
    // `signBit` reads the format's sign position, not FP32's.
    val dToward = d32.map(fromF32(_, RTZ))
    val dAway = d32.zip(dToward).map { case (x, t) => mux(signBit(t), fromF32(x, RDN), fromF32(x, RUP)) }
    val tmin = fromF32(tmin32, RDN)
    val tmax = fromF32(tmax32, RUP)
    val err = or(
      any(oLo.map(isNonFinite) ++ oHi.map(isNonFinite) ++ dAway.map(isNonFinite) ++ Seq(isNaN(tmin), isNaN(tmax))),
      all(dAway.map(isZero))
    )
    // Two operands per axis (d away and toward zero), so two reciprocals, not a recipPair.
    val rcpLo = dAway.map(x => recip(abs(x), RTZ))
    val rcpHi = dToward.map(x => recip(abs(x), RUP))
    RayK(oLo, dAway, tmin, err, rcpLo, rcpHi, None, Some(oHi))
  }

  /** The narrowing of [[apply]] for one unit: o, d, tmin, the error bit, tmax,
    * (`withRcp`: for the box lanes) the reciprocals and (`withNearest` too:
    * for the watertight shear) |1/d| rounded to nearest, else Nil.
    */
  private def narrowed[F, B](
      ar: KernelArith[F, B],
      o32: Seq[F],
      d32: Seq[F],
      tmin32: F,
      tmax32: F,
      rounding: BoxRounding,
      withRcp: Boolean,
      withNearest: Boolean
  ): (RayK[F, B], F, Seq[F]) = {
    import ar._
    val cons = rounding == BoxRounding.Conservative
    val o = o32.map(fromF32(_, RNE))
    val d = d32.map(fromF32(_, RNE))
    val tmin = fromF32(tmin32, if (cons) RDN else RNE)
    val tmax = fromF32(tmax32, if (cons) RUP else RNE)
    val err = or(any(o.map(isNonFinite) ++ d.map(isNonFinite) ++ Seq(isNaN(tmin), isNaN(tmax))), all(d.map(isZero)))
    val mag = d.map(abs)
    // 1/|d| is positive, so RTZ = RDN. RTZ never overflows: for 0 < |d| <= 2^-(emax+1)
    // it gives maxFinite where RNE gives inf (the origin-on-plane 0 * inf case).
    // |d| = 0 gives inf in every mode; such an axis is flat (B6) and not used.
    // Conservative: both of one |d| (recipPair: hardware shares the quotient), and with
    // `withNearest` the shear's RNE too, from the same quotient (recipModes).
    val (rcpLo, rcpHi, rcpNearest) =
      if (!withRcp) (Nil, Nil, Nil)
      else if (cons && withNearest) {
        val r = mag.map(recipModes(_, Seq(RTZ, RUP, RNE)))
        (r.map(_(0)), r.map(_(1)), r.map(_(2)))
      } else if (cons) { val (lo, hi) = mag.map(recipPair(_, RTZ, RUP)).unzip; (lo, hi, Nil) }
      else { val r = mag.map(recip(_, RNE)); (r, r, if (withNearest) r else Nil) }
    (RayK(o, d, tmin, err, rcpLo, rcpHi, None), tmax, rcpNearest)
  }

  /** R2-R5. `rcpMag` is |1/d| rounded to nearest when the setup already has it (the box lanes'
    * reciprocal units give it beside their bounds); None computes 1/d[kz] on its own.
    */
  private def shearOf[F, B](ar: KernelArith[F, B], d: Seq[F], mag: Seq[F], rcpMag: Option[Seq[F]]): Shear[F, B] = {
    import ar._
    // R2: largest |d|, ties to the lowest axis (strict >). On non-NaN magnitudes
    // IEEE < is the unsigned order of the magnitude bits.
    val g1 = lt(mag(0), mag(1))
    // The larger of the first two is registered before its compare with the third: the select stacked on the
    // comparator's carry chain was the setup's longest path.
    val g2 = lt(cut(mux(g1, mag(1), mag(0))), mag(2))
    val kz = Seq(and(not(g2), not(g1)), and(not(g2), g1), g2)
    // R3: kx = kz+1, ky = kz+2 (mod 3), swapped when d[kz] is negative.
    val kxUp = Seq(kz(2), kz(0), kz(1))
    val kyUp = Seq(kz(1), kz(2), kz(0))
    val dz = select(kz, d)
    val flip = signBit(dz)
    val kx = kxUp.indices.map(i => muxB(flip, kyUp(i), kxUp(i)))
    val ky = kxUp.indices.map(i => muxB(flip, kxUp(i), kyUp(i)))
    // R4: Sz = 1/d[kz] (RNE). RNE is sign-symmetric, so -(1/|d|) = 1/(-|d|) bit for bit.
    val sz = rcpMag match {
      // Registered before the multiplies: the select and the sign flip stacked on a multiplier's first stage.
      case Some(r) => val rz = select(kz, r); cut(mux(flip, neg(rz), rz))
      case None    => recip(dz, RNE)
    }
    // R5
    Shear(kx, ky, kz, mul(select(kx, d), sz, RNE), mul(select(ky, d), sz, RNE), sz)
  }
}
