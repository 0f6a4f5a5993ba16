package rtaccel.datapath

import rtaccel.fp.RoundingMode.{RDN, RUP}

/** The per-node half of the grid box test (docs/kernels.md, "Box tests in
  * the node's grid"), written once for every interpretation like
  * [[BoxKernel]]: per axis of a quantized node, bounds on the distance to the
  * child planes' entry-side base and on one grid step, shared by all K
  * children; per node a reference distance `t0` every bound is taken
  * relative to. The per-child half is integer (rtaccel.traversal.GridLane).
  *
  * Plane q (0..qMax) of an axis lies at origin + q 2^s. Along the ray the
  * entry side is q = 0 when d >= 0 and q = qMax when d < 0, so the planes are
  * renumbered q' = q (d >= 0) or qMax - q (d < 0), and then for every child
  * plane t(q') = (diff + q' 2^s) / |d| with diff = base' - o (d >= 0) or
  * o - base' (d < 0), base' the q' = 0 plane. Every quantity below is a bound
  * rounded outward (RDN for a lower, RUP for an upper one), so for every
  * q' >= 0, tbLo + q' 2^s R- <= t(q') <= tbHi + q' 2^s R+, with R- <= 1/|d| <= R+
  * the ray's reciprocals ([[RayK]]). Relative to t0, t(q') - t0 = (q' - c) 2^s / |d|
  * with c the ray's grid coordinate at t0: `d` must be the exact direction
  * (one format for box and triangle, or an FP32 box format, where it is the
  * FP32 ray's). A flat axis (d = +-0) has no distances:
  * its test is the origin's grid coordinate c' = -diff / 2^s, which lies in
  * [-diffHi, -diffLo] / 2^s.
  */
object GridKernel {

  /** `cLo`, `cHi`: bounds on c 2^s, c the grid coordinate (in q') of the ray's point at t0. */
  final case class Axis[F, B](flat: B, neg: B, diffLo: F, diffHi: F, cLo: F, cHi: F)

  /** `tminR`/`tmaxR`: the ray's interval relative to `t0` (down, up). */
  final case class Node[F, B](axes: Seq[Axis[F, B]], t0: F, tminR: F, tmaxR: F, err: B)

  /** @param origin the q = 0 plane per axis (exact in `ar.fmt`)
    * @param span   qMax 2^s per axis (exact in `ar.fmt`)
    * @param tmax   the ray's tmax already in `ar.fmt` (rounded up, [[BoxKernel.narrowTmax]])
    */
  def apply[F, B](ar: KernelArith[F, B], ray: RayK[F, B], tmax: F, origin: Seq[F], span: Seq[F]): Node[F, B] = {
    import ar._
    val pre = (0 until 3).map { i =>
      val (o, oHi, d) = (ray.o(i), ray.oHi.fold(ray.o(i))(_(i)), ray.d(i))
      val neg = signBit(d)
      // base' = origin + span when d < 0; its bounds (exact for images nori-bridge writes, QuantNode).
      val (farLo, farHi) = addDnUp(origin(i), span(i))
      // One subtractor per bound, operands picked by the sign: diffLo <= diff <= diffHi. The picks are
      // registered (cut): a select in front of a subtractor's first stage is past 5 ns by the delay model
      // (docs/fmax.md) when the per-node stage is synthesised alone.
      val diffLo = sub(cut(mux(neg, o, origin(i))), cut(mux(neg, farHi, oHi)), RDN)
      val diffHi = sub(cut(mux(neg, oHi, origin(i))), cut(mux(neg, farLo, o)), RUP)
      // BoxKernel's rule: the reciprocal that moves the product outward.
      // The pick is registered (cut) before the multiply: the sign-and-nonzero test of the subtractor's answer
      // and the select, in front of the multiplier's exponent add, were the grid unit's longest path.
      val tbLo = mul(diffLo, cut(mux(ltZero(diffLo), ray.rcpHi(i), ray.rcpLo(i))), RDN)
      (isZero(d), neg, diffLo, diffHi, tbLo, abs(d))
    }
    // t0: the grid's entry distance, rounded down (any finite value keeps the
    // test conservative; this one keeps every relative bound of a child the
    // ray enters within qMax steps of 0). 0 when no axis gives a finite one.
    val t0Raw = pre.foldLeft(negInf) { case (m, (flat, _, _, _, tbLo, _)) => max(m, mux(flat, negInf, tbLo)) }
    // Registered (cut) before the units that read it: the infinity test and the select after the compare's
    // answer, in front of a unit's first stage, were the grid unit's longest path.
    val t0 = cut(mux(isNonFinite(t0Raw), posZero, t0Raw))
    // t(q') - t0 = (q' - c) 2^s / |d| with c 2^s = t0 |d| - diff: the ray's grid
    // coordinate at t0, which for a ray through the grid lies in 0..qMax.
    val axes = pre.map { case (flat, neg, diffLo, diffHi, _, absD) =>
      val (pLo, pHi) = mulDnUp(t0, absD)
      Axis(flat, neg, diffLo, diffHi, sub(pLo, diffHi, RDN), sub(pHi, diffLo, RUP))
    }
    Node(axes, t0, sub(ray.tmin, t0, RDN), sub(tmax, t0, RUP), ray.err)
  }
}
