package rtaccel.datapath

import rtaccel.ErrorFlags
import rtaccel.fp.{FloatFormat, FpModel, RoundingMode}
import rtaccel.golden.{ArithGolden, PreparedGolden, RayRecord}
import rtaccel.scene.{NodeRecord, TriangleRecord}
import rtaccel.bvh.QuantNode
import rtaccel.traversal.{GridLane, GridNode, GridParams}

/** The golden model of a [[FloatDatapath]]: the same kernels run on bit
  * patterns through FpModel ([[GoldenArith]]), so it is the hardware's
  * operation order by construction, split formats included (box kernel in
  * `boxArith`, triangle kernel in `triArith`, tmax kept in the triangle format
  * and narrowed by [[BoxKernel.narrowTmax]] for every box test, as each box
  * lane does). Statics are the kernel's [[SplitRay]].
  */
final case class FloatGolden(dp: FloatDatapath) extends ArithGolden[SplitRay[BigInt, Boolean]] {
  type Ray = SplitRay[BigInt, Boolean]
  def boxFormat: FloatFormat = dp.boxFmt
  def triFormat: FloatFormat = dp.triFmt
  val boxArith = new GoldenArith(dp.boxFmt)
  val triArith = if (dp.split) new GoldenArith(dp.triFmt) else boxArith

  /** Per-ray setup from FP32 bit patterns: both units' constants, tmax in the
    * triangle format, and the error bit.
    */
  def setupErr(o: Seq[BigInt], d: Seq[BigInt], tmin: BigInt, tmax: BigInt): (Ray, BigInt, Boolean) =
    RayKernel.split(boxArith, triArith, o, d, tmin, tmax, dp.rounding, dp.test)
  def setup(o: Seq[BigInt], d: Seq[BigInt], tmin: BigInt, tmax: BigInt): (Ray, BigInt) = {
    val (k, t, _) = setupErr(o, d, tmin, tmax)
    (k, t)
  }

  def prep(ray: RayRecord): PreparedGolden[Ray] = {
    val (k, tmax, err) = setupErr(ray.origin.map(BigInt(_)), ray.dir.map(BigInt(_)), BigInt(ray.tmin), BigInt(ray.tmax))
    PreparedGolden(k, tmax, k.box.d.map(dp.boxFmt.sign), if (err) 1 << ErrorFlags.InvalidRay else 0)
  }

  /** Box test on FP32 bounds, `tmax` in the triangle format: (hit, near in the box format). */
  def boxTest(s: Ray, tmax: BigInt, bmin: Seq[BigInt], bmax: Seq[BigInt]): (Boolean, BigInt) = {
    val o =
      BoxKernel(boxArith, dp.rounding, s.box, BoxKernel.narrowTmax(boxArith, dp.rounding, tmax, dp.triFmt), bmin, bmax)
    (o.hit, o.near)
  }
  def box(s: Ray, tmax: BigInt, node: NodeRecord): (Boolean, BigInt) =
    boxTest(s, tmax, node.boxMin.map(BigInt(_)), node.boxMax.map(BigInt(_)))

  /** GridBboxIntersect's answer: the node stage once (tmax widened to FP32 as
    * GridNodeStage does), a lane per child. A scale exponent outside
    * ExpMin..ExpMax hits nothing (its badScale).
    */
  override def gridBox(
      s: Ray,
      tmax: BigInt,
      p: GridParams,
      g: QuantNode.GridSoft,
      present: Seq[Boolean]
  ): Seq[(Boolean, BigInt)] = {
    require(dp.boxFmt == FloatFormat.FP32, s"FloatGolden ${dp.name}: the grid box test needs FP32 box constants")
    if (g.exp.exists(e => e < QuantNode.ExpMin || e > QuantNode.ExpMax)) present.map(_ => (false, BigInt(0)))
    else {
      val t = BoxKernel.narrowTmax(boxArith, BoxRounding.Conservative, tmax, dp.triFmt)
      val n = GridNode.soft(dp.boxFmt, p, s.box, t, g.origin.map(BigInt(_)), g.exp.map(_ - 127))
      present.indices.map { i =>
        val o = GridLane.soft(p, n, g.qMin(i), g.qMax(i), present(i))
        (o.hit, o.near)
      }
    }
  }

  /** Triangle test on nine FP32 vertex words (p0, p1, p2). */
  def primTest(s: Ray, tmax: BigInt, p: Seq[BigInt]): PrimOut[BigInt, Boolean] = dp.test match {
    case TriangleTest.Moller     => MollerKernel(triArith, s.tri, tmax, p)
    case TriangleTest.Watertight => WatertightKernel(triArith, s.tri, tmax, p)
  }
  def prim(s: Ray, tmax: BigInt, tri: TriangleRecord): Option[(BigInt, BigInt, BigInt)] = {
    val o = primTest(s, tmax, tri.vertexWords.map(BigInt(_)))
    Option.when(o.hit)((o.t, o.u, o.v))
  }

  /** Exact widening of a triangle-format value (the mode does not matter). */
  def toFloat32(x: BigInt): Long =
    (if (dp.triFmt == FloatFormat.FP32) x else FpModel.toFloat32(dp.triFmt, RoundingMode.RNE, x)).toLong
}
