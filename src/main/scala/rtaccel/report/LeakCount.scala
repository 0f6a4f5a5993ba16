package rtaccel.report

import rtaccel.datapath._
import rtaccel.fp.FpModel

import scala.util.Random

/** Leak counts on a [[ClosedMesh]] with a datapath's golden model (bit-exact
  * with its hardware): rays from inside origins aimed exactly at every vertex
  * and at every edge midpoint (d = target - o in FP32, tmin = 0, tmax = inf);
  * a leak is a ray that hits no triangle.
  *
  * Which triangles are tried: the ones around the target first; only if none
  * hits, every triangle the ray passes near (a double-precision bounding-sphere
  * test with margin 1.5 r + 2^-(p-4) (|c| + radius), far above the kernel's
  * rounding error in a format of precision p). So a leak is only reported when
  * no triangle of the mesh the ray can reach hits.
  */
object LeakCount {
  final case class Result(vertexRays: Int, vertexLeaks: Int, edgeRays: Int, edgeLeaks: Int, zeroArea: Int)

  def apply(g: FloatGolden, mesh: ClosedMesh, origins: Int, radius: Double, offset: Double, rng: Random): Result = {
    val fmt = g.triFormat
    val verts = mesh.vertices.map(_.map(x => FpModel.f32Bits(x)))
    val vFmt = verts.map(_.map(g.triArith.fromF32(_, rtaccel.fp.RoundingMode.RNE)))
    val tri = mesh.faces.map(f => f.flatMap(verts))
    val zeroArea = mesh.faces.count { f =>
      val Seq(a, b, c) = f.map(vFmt); a == b || b == c || a == c
    }
    val centre = mesh.faces.map(f => (0 until 3).map(k => f.map(mesh.vertices(_)(k).toDouble).sum / 3))
    val rad = mesh.faces.indices.map(i => mesh.faces(i).map(v => dist(mesh.vertices(v).map(_.toDouble), centre(i))).max)
    val margin = math.pow(2, -(fmt.precision - 4))
    var (vRays, vLeaks, eRays, eLeaks) = (0, 0, 0, 0)
    for (_ <- 0 until origins) {
      val o = inBall(rng, radius / 2).map(x => (x + offset).toFloat)
      def leaks(target: Seq[Float], near: Seq[Int]): Boolean = {
        val d = target.zip(o).map { case (t, oo) => t - oo }
        val (ray, tmax) =
          g.setup(o.map(FpModel.f32Bits), d.map(FpModel.f32Bits), BigInt(0), FpModel.f32Bits(Float.PositiveInfinity))
        def hits(i: Int) = g.primTest(ray, tmax, tri(i)).hit
        !(near.exists(hits) || mesh.faces.indices.exists { i =>
          !near.contains(i) && passesNear(o, d, centre(i), 1.5 * rad(i) + margin * (norm(centre(i)) + radius)) && hits(
            i
          )
        })
      }
      for ((v, i) <- mesh.vertices.zipWithIndex) { vRays += 1; if (leaks(v, mesh.vertexFaces(i))) vLeaks += 1 }
      for (((a, b), (f1, f2)) <- mesh.edges.zip(mesh.edgeFaces)) {
        val mid = mesh.vertices(a).zip(mesh.vertices(b)).map { case (x, y) => ((x.toDouble + y) / 2).toFloat }
        eRays += 1
        if (leaks(mid, Seq(f1, f2))) eLeaks += 1
      }
    }
    Result(vRays, vLeaks, eRays, eLeaks, zeroArea)
  }

  private def inBall(rng: Random, r: Double): Seq[Double] = {
    var p = Seq.fill(3)(2 * rng.nextDouble() - 1)
    while (norm(p) > 1) p = Seq.fill(3)(2 * rng.nextDouble() - 1)
    p.map(_ * r)
  }
  private def norm(p: Seq[Double]) = math.sqrt(p.map(x => x * x).sum)
  private def dist(a: Seq[Double], b: Seq[Double]) = norm(a.zip(b).map { case (x, y) => x - y })

  /** Distance from `c` to the half-line o + t d (t >= 0) is at most `r`. */
  private def passesNear(o: Seq[Float], d: Seq[Float], c: Seq[Double], r: Double): Boolean = {
    val (od, dd) = (o.map(_.toDouble), d.map(_.toDouble))
    val rel = c.zip(od).map { case (x, y) => x - y }
    val t = math.max(0, rel.zip(dd).map { case (x, y) => x * y }.sum / dd.map(x => x * x).sum)
    dist(od.zip(dd).map { case (x, y) => x + t * y }, c) <= r
  }
}
