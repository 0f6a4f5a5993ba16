package rtaccel.datapath

import rtaccel.fp.{FloatFormat, FpModel}
import rtaccel.fp.RoundingMode.RNE

/** A triangle test's answer: hit, and t, u, v (+0 on a miss). */
final case class PrimOut[F, B](hit: B, t: F, u: F, v: F)

/** Shared pieces of both triangle tests. */
object TriangleCommon {

  /** Vertices narrowed to nearest: a shared FP32 vertex narrows to the same
    * value in every triangle, which keeps a closed mesh closed in any format.
    */
  def vertices[F, B](ar: KernelArith[F, B], p32: Seq[F]): Seq[Seq[F]] =
    p32.grouped(3).map(_.map(ar.fromF32(_, RNE))).toSeq

  /** Section 6: two vertices equal component-wise (IEEE ==). Never a hit. */
  def coincident[F, B](ar: KernelArith[F, B], p: Seq[Seq[F]]): B = {
    import ar._
    def same(a: Seq[F], b: Seq[F]) = all(a.indices.map(i => ar.eq(a(i), b(i))))
    any(Seq(same(p(0), p(1)), same(p(1), p(2)), same(p(0), p(2))))
  }

  /** M14/W11: t, u, v on a hit, +0 on a miss. */
  def answer[F, B](ar: KernelArith[F, B], hit: B, t: F, u: F, v: F): PrimOut[F, B] = {
    import ar._
    PrimOut(hit, mux(hit, t, posZero), mux(hit, u, posZero), mux(hit, v, posZero))
  }
}

/** Nori-compatible Moller-Trumbore (docs/kernels.md section 4), Eigen's
  * operation order for cross and dot. All steps RNE.
  */
object MollerKernel {

  /** Nori's |det| cut-off, the float nearest 1e-8 (bits 322bcc77), narrowed to
    * nearest. It is Nori's constant, not an error bound; in a format whose
    * smallest subnormal exceeds it, it becomes 0 and only det = 0 is parallel.
    */
  def epsilon(fmt: FloatFormat): BigInt = FpModel.fromFloat32(fmt, RNE, BigInt(0x322bcc77L))

  def apply[F, B](ar: KernelArith[F, B], ray: RayK[F, B], tmax: F, p32: Seq[F]): PrimOut[F, B] = {
    import ar._
    val p = TriangleCommon.vertices(ar, p32)
    def diff(a: Seq[F], b: Seq[F]) = a.indices.map(i => sub(a(i), b(i), RNE))
    def cross(a: Seq[F], b: Seq[F]) = Seq((0, 1, 2), (1, 2, 0), (2, 0, 1)).map { case (_, j, k) =>
      sub(mul(a(j), b(k), RNE), mul(a(k), b(j), RNE), RNE)
    }
    def dot(a: Seq[F], b: Seq[F]) = {
      val m = a.indices.map(i => mul(a(i), b(i), RNE))
      add(m(0), add(m(1), m(2), RNE), RNE)
    }
    val edge1 = diff(p(1), p(0)) // M1
    val edge2 = diff(p(2), p(0)) // M2
    val tvec = diff(ray.o, p(0)) // M3
    val pvec = cross(ray.d, edge2) // M4
    val det = dot(edge1, pvec) // M5
    val eps = epsilon(fmt)
    val parallel = and(gt(det, const(fmt.negate(eps))), lt(det, const(eps))) // M6
    val invDet = recip(det, RNE) // M7
    val u = mul(dot(tvec, pvec), invDet, RNE) // M8
    val qvec = cross(tvec, edge1) // M9
    val v = mul(dot(ray.d, qvec), invDet, RNE) // M10
    val s = add(u, v, RNE) // M11
    val t = mul(dot(edge2, qvec), invDet, RNE) // M12
    val one = const(fmt.one(false))
    val hit = all(Seq( // M13
      not(ray.err),
      not(TriangleCommon.coincident(ar, p)),
      not(parallel),
      not(or(ltZero(u), gt(u, one))),
      not(isNaN(u)),
      not(or(ltZero(v), gt(s, one))),
      not(isNaN(v)),
      ge(t, ray.tmin),
      le(t, tmax)
    ))
    TriangleCommon.answer(ar, hit, t, u, v)
  }
}

/** Watertight test (docs/kernels.md section 5): shear and scale into ray
  * space, edge functions, and the tie rule: an edge value of zero counts as
  * inside, a miss needs a strictly negative and a strictly positive one.
  * E(Q, P) == -E(P, Q) bit for bit (products commute, RNE is sign-symmetric),
  * so two faces sharing an edge see exactly opposite values and a ray through
  * the edge is inside at least one. All steps RNE.
  */
object WatertightKernel {
  def apply[F, B](ar: KernelArith[F, B], ray: RayK[F, B], tmax: F, p32: Seq[F]): PrimOut[F, B] = {
    import ar._
    val sh = ray.shear.getOrElse(throw new IllegalArgumentException("watertight test needs the shear constants"))
    val p = TriangleCommon.vertices(ar, p32)
    val sheared = p.map { v =>
      val r = v.indices.map(i => sub(v(i), ray.o(i), RNE)) // W1
      // The picks are registered: picked in front of a unit, a select ran into the multipliers' operand
      // tests (5.24 ns) and the subtractor's exponent distance (5.64 ns). The z pick costs a cycle of
      // PrimIntersect's latency; the x and y picks wait for the products anyway.
      val rz = cut(select(sh.kz, r))
      val px = sub(cut(select(sh.kx, r)), mul(sh.sx, rz, RNE), RNE) // W2
      val py = sub(cut(select(sh.ky, r)), mul(sh.sy, rz, RNE), RNE)
      (px, py, mul(sh.sz, rz, RNE)) // W3
    }
    val Seq(a, b, c) = sheared
    def edge(pp: (F, F, F), q: (F, F, F)) = sub(mul(pp._1, q._2, RNE), mul(pp._2, q._1, RNE), RNE)
    val (u, v, w) = (edge(c, b), edge(a, c), edge(b, a)) // W4
    val outside = and(any(Seq(u, v, w).map(ltZero)), any(Seq(u, v, w).map(gtZero))) // W5
    val det = add(add(u, v, RNE), w, RNE) // W6
    val tScaled = add(add(mul(u, a._3, RNE), mul(v, b._3, RNE), RNE), mul(w, c._3, RNE), RNE) // W7
    val rcpDet = recip(det, RNE) // W8
    // W9: a zero numerator stays +0 even when rcpDet overflowed (no 0 * inf).
    def scale(x: F) = mux(isZero(x), posZero, mul(x, rcpDet, RNE))
    // t is registered ahead of its compares with tmin and tmax: the zero test's select in front of a compare
    // was PrimIntersect's longest path (5.55 ns). One cycle of its latency.
    val (t, uu, vv) = (cut(scale(tScaled)), scale(v), scale(w))
    val hit = all(Seq( // W10
      not(ray.err),
      not(TriangleCommon.coincident(ar, p)),
      not(outside),
      not(isZero(det)),
      not(isNonFinite(det)),
      ge(t, ray.tmin),
      le(t, tmax)
    ))
    TriangleCommon.answer(ar, hit, t, uu, vv)
  }
}
