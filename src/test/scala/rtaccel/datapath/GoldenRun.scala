package rtaccel.datapath

import rtaccel.fp.FloatFormat

/** Expected outputs of a datapath's golden model for one vector-file case,
  * packed the way the .out files and [[DatapathHarness]] lay them out.
  */
object GoldenRun {
  final case class BoxExp(err: Boolean, hit: Boolean, near: BigInt)
  final case class PrimExp(err: Boolean, hit: Boolean, t: BigInt, u: BigInt, v: BigInt)

  def box(g: FloatGolden, c: KernelCase): BoxExp = {
    // err: the ray prep's InvalidRay flag, either unit's (RayKernel.split).
    val (ray, tmax, err) = g.setupErr(c.o, c.d, c.tmin, c.tmax)
    val (hit, near) = g.boxTest(ray, tmax, c.bmin, c.bmax)
    BoxExp(err, hit, near)
  }

  def prim(g: FloatGolden, c: KernelCase): PrimExp = {
    val (ray, tmax, err) = g.setupErr(c.o, c.d, c.tmin, c.tmax)
    val o = g.primTest(ray, tmax, c.verts)
    PrimExp(err, o.hit, o.t, o.u, o.v)
  }

  /** The formats every narrow-format check runs in (FP32 is checked against the HLS .out files). */
  val narrowFormats: Seq[FloatFormat] =
    Seq(FloatFormat(8, 15), FloatFormat(8, 10), FloatFormat(6, 9), FloatFormat(5, 10))

  /** `.out` box line outputs. */
  def boxOf(c: KernelCase): BoxExp = BoxExp(c.out(1) == 1, c.out(0) == 1, c.out(2))
  def primOf(c: KernelCase): PrimExp = PrimExp(c.out(1) == 1, c.out(0) == 1, c.out(2), c.out(3), c.out(4))
}
