package rtaccel.report

import scala.collection.mutable
import scala.util.Random

/** A closed test mesh for the leak count: an icosahedron subdivided `level`
  * times, each vertex moved radially by a seeded factor in [0.9, 1.1] (so no
  * two faces are coplanar, as in pbrt's watertightness test), scaled, offset
  * and rounded to FP32. Faces index shared vertices, so the FP32 mesh is
  * closed, and so is its narrowing to any format (a vertex narrows to one
  * value). Same construction as hls/closed_mesh.cpp, but not the same
  * random stream: the figures are comparable, not identical.
  */
final case class ClosedMesh(
    vertices: IndexedSeq[Seq[Float]],
    faces: IndexedSeq[Seq[Int]],
    edges: IndexedSeq[(Int, Int)],
    edgeFaces: IndexedSeq[(Int, Int)],
    vertexFaces: IndexedSeq[Seq[Int]]
)

object ClosedMesh {
  def apply(level: Int, radius: Double, offset: Double, rng: Random): ClosedMesh = {
    val t = (1 + math.sqrt(5)) / 2
    val pts = mutable.ArrayBuffer[Seq[Double]](
      Seq(-1, t, 0),
      Seq(1, t, 0),
      Seq(-1, -t, 0),
      Seq(1, -t, 0),
      Seq(0, -1, t),
      Seq(0, 1, t),
      Seq(0, -1, -t),
      Seq(0, 1, -t),
      Seq(t, 0, -1),
      Seq(t, 0, 1),
      Seq(-t, 0, -1),
      Seq(-t, 0, 1)
    ).map(unit)
    var faces: Seq[Seq[Int]] = Seq(
      Seq(0, 11, 5),
      Seq(0, 5, 1),
      Seq(0, 1, 7),
      Seq(0, 7, 10),
      Seq(0, 10, 11),
      Seq(1, 5, 9),
      Seq(5, 11, 4),
      Seq(11, 10, 2),
      Seq(10, 7, 6),
      Seq(7, 1, 8),
      Seq(3, 9, 4),
      Seq(3, 4, 2),
      Seq(3, 2, 6),
      Seq(3, 6, 8),
      Seq(3, 8, 9),
      Seq(4, 9, 5),
      Seq(2, 4, 11),
      Seq(6, 2, 10),
      Seq(8, 6, 7),
      Seq(9, 8, 1)
    )
    for (_ <- 0 until level) {
      val mid = mutable.Map.empty[(Int, Int), Int]
      def m(a: Int, b: Int) = mid.getOrElseUpdate(
        (a min b, a max b), {
          pts += unit(pts(a).zip(pts(b)).map { case (x, y) => x + y }); pts.size - 1
        }
      )
      faces = faces.flatMap { case Seq(a, b, c) =>
        val (ab, bc, ca) = (m(a, b), m(b, c), m(c, a))
        Seq(Seq(a, ab, ca), Seq(b, bc, ab), Seq(c, ca, bc), Seq(ab, bc, ca))
      }
    }
    val verts = pts.toIndexedSeq.map { p =>
      val s = radius * (0.9 + 0.2 * rng.nextDouble())
      p.map(x => (x * s + offset).toFloat)
    }
    val byEdge = mutable.LinkedHashMap.empty[(Int, Int), List[Int]]
    for ((f, i) <- faces.zipWithIndex; k <- 0 until 3) {
      val (a, b) = (f(k), f((k + 1) % 3))
      byEdge((a min b, a max b)) = i :: byEdge.getOrElse((a min b, a max b), Nil)
    }
    require(byEdge.values.forall(_.size == 2), "ClosedMesh: an edge does not have exactly two faces")
    val vf = Array.fill(verts.size)(List.empty[Int])
    for ((f, i) <- faces.zipWithIndex; v <- f) vf(v) = i :: vf(v)
    ClosedMesh(
      verts,
      faces.toIndexedSeq,
      byEdge.keys.toIndexedSeq,
      byEdge.values.map { case List(x, y) => (x, y); case _ => sys.error("unreachable") }.toIndexedSeq,
      vf.toIndexedSeq.map(_.reverse)
    )
  }

  private def unit(p: Seq[Double]): Seq[Double] = { val n = math.sqrt(p.map(x => x * x).sum); p.map(_ / n) }
}
