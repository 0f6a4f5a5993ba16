package rtaccel.datapath

import rtaccel.ErrorFlags
import rtaccel.fp.{FloatFormat, FpModel, RoundingMode}
import rtaccel.golden.{ArithGolden, PreparedGolden, RayRecord}
import rtaccel.scene.{NodeRecord, TriangleRecord}

/** The golden model of a [[FloatDatapath]]: the same kernels run on bit
  * patterns through FpModel ([[GoldenArith]]), so it is the hardware's
  * operation order by construction. Statics are the kernel's [[RayK]].
  */
final case class FloatGolden(dp: FloatDatapath) extends ArithGolden[RayK[BigInt, Boolean]] {
  type Ray = RayK[BigInt, Boolean]
  def format: FloatFormat = dp.fmt
  val arith = new GoldenArith(dp.fmt)

  /** Per-ray setup from FP32 bit patterns: the constants and tmax in the format. */
  def setup(o: Seq[BigInt], d: Seq[BigInt], tmin: BigInt, tmax: BigInt): (Ray, BigInt) =
    RayKernel(arith, o, d, tmin, tmax, dp.rounding, dp.test)

  def prep(ray: RayRecord): PreparedGolden[Ray] = {
    val (k, tmax) = setup(ray.origin.map(BigInt(_)), ray.dir.map(BigInt(_)), BigInt(ray.tmin), BigInt(ray.tmax))
    PreparedGolden(k, tmax, k.d.map(dp.fmt.sign), if (k.err) 1 << ErrorFlags.InvalidRay else 0)
  }

  /** Box test on FP32 bounds: (hit, near). */
  def boxTest(s: Ray, tmax: BigInt, bmin: Seq[BigInt], bmax: Seq[BigInt]): (Boolean, BigInt) = {
    val o = BoxKernel(arith, dp.rounding, s, tmax, bmin, bmax)
    (o.hit, o.near)
  }
  def box(s: Ray, tmax: BigInt, node: NodeRecord): (Boolean, BigInt) =
    boxTest(s, tmax, node.boxMin.map(BigInt(_)), node.boxMax.map(BigInt(_)))

  /** Triangle test on nine FP32 vertex words (p0, p1, p2). */
  def primTest(s: Ray, tmax: BigInt, p: Seq[BigInt]): PrimOut[BigInt, Boolean] = dp.test match {
    case TriangleTest.Moller     => MollerKernel(arith, s, tmax, p)
    case TriangleTest.Watertight => WatertightKernel(arith, s, tmax, p)
  }
  def prim(s: Ray, tmax: BigInt, tri: TriangleRecord): Option[(BigInt, BigInt, BigInt)] = {
    val o = primTest(s, tmax, tri.vertexWords.map(BigInt(_)))
    Option.when(o.hit)((o.t, o.u, o.v))
  }

  /** Exact widening (the mode does not matter). */
  def toFloat32(x: BigInt): Long =
    (if (dp.fmt == FloatFormat.FP32) x else FpModel.toFloat32(dp.fmt, RoundingMode.RNE, x)).toLong
}
