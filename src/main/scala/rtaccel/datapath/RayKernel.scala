package rtaccel.datapath

import rtaccel.fp.RoundingMode.{RDN, RNE, RUP, RTZ}

/** Watertight shear constants (docs/kernels.md R2-R5): one-hot axes and Sx, Sy, Sz. */
final case class Shear[F, B](kx: Seq[B], ky: Seq[B], kz: Seq[B], sx: F, sy: F, sz: F)

/** A ray's per-ray constants in the datapath format, under any interpretation.
  *
  * @param rcpLo |1/d[i]| rounded toward zero (Conservative) or to nearest (Nearest)
  * @param rcpHi |1/d[i]| rounded away from zero (Conservative); `rcpLo` in Nearest mode
  * @param err   the error bit R6, evaluated on the format's values
  */
final case class RayK[F, B](o: Seq[F], d: Seq[F], tmin: F, err: B, rcpLo: Seq[F], rcpHi: Seq[F],
    shear: Option[Shear[F, B]])

/** Per-ray setup (docs/kernels.md section 2), written once for every interpretation. */
object RayKernel {
  /** The ray's constants and its tmax, from FP32 inputs.
    *
    * Narrowing: o and d round to nearest (this is the ray the datapath traces;
    * the conservative guarantee is relative to it). In Conservative mode tmin
    * rounds down and tmax up, which only widens [tmin, tmax].
    * Errors are judged on the narrowed values: an origin that overflows the
    * format, or a direction that underflows to zero, cannot be traced in it.
    */
  def apply[F, B](ar: KernelArith[F, B], o32: Seq[F], d32: Seq[F], tmin32: F, tmax32: F,
      rounding: BoxRounding, test: TriangleTest): (RayK[F, B], F) = {
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
    val rcpLo = mag.map(recip(_, if (cons) RTZ else RNE))
    val rcpHi = if (cons) mag.map(recip(_, RUP)) else rcpLo
    val shear = Option.when(test == TriangleTest.Watertight)(shearOf(ar, d, mag, if (cons) None else Some(rcpLo)))
    (RayK(o, d, tmin, err, rcpLo, rcpHi, shear), tmax)
  }

  /** R2-R5. `rcpMag` is |1/d| rounded to nearest when the box already has it. */
  private def shearOf[F, B](ar: KernelArith[F, B], d: Seq[F], mag: Seq[F], rcpMag: Option[Seq[F]]): Shear[F, B] = {
    import ar._
    // R2: largest |d|, ties to the lowest axis (strict >). On non-NaN magnitudes
    // IEEE < is the unsigned order of the magnitude bits.
    val g1 = lt(mag(0), mag(1))
    val g2 = lt(mux(g1, mag(1), mag(0)), mag(2))
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
      case Some(r) => val rz = select(kz, r); mux(flip, neg(rz), rz)
      case None    => recip(dz, RNE)
    }
    // R5
    Shear(kx, ky, kz, mul(select(kx, d), sz, RNE), mul(select(ky, d), sz, RNE), sz)
  }
}
