package rtaccel.study

import rtaccel.AccelConfig
import rtaccel.golden.{ArithGolden, RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage

import scala.collection.mutable

/** One scene read of the golden walk, in the hardware's order. */
sealed trait SceneRead

/** Node `index` (one record of the image's node layout). */
final case class NodeRead(index: Long) extends SceneRead

/** A leaf entered: its triangle slots `first` until `first + count`. Free in a design that reads triangle by triangle. */
final case class LeafRead(first: Long, count: Int) extends SceneRead

/** Triangle slot `index`, tested. Free in a design that reads whole leaves. */
final case class TriRead(index: Long) extends SceneRead

/** Every scene read of one ray: the golden walk's node fetches (the hardware's node reads, one per node test), the
  * leaves it enters and the triangles it tests (TraversalGolden.trace).
  */
final case class RayReads(ray: RayRecord, reads: IndexedSeq[SceneRead])

object RayReads {
  def of[S](cfg: AccelConfig, img: MemoryImage, arith: ArithGolden[S], ray: RayRecord): RayReads = {
    val b = mutable.ArrayBuffer.empty[SceneRead]
    TraversalGolden.trace(
      cfg,
      img,
      arith,
      ray,
      i => b += NodeRead(i),
      (f, n) => b += LeafRead(f, n),
      j => b += TriRead(j)
    )
    RayReads(ray, b.toIndexedSeq)
  }

  /** At most `maxRays` of `rays`, strided over the set as `make bench` samples it. */
  def sample[A](rays: IndexedSeq[A], maxRays: Int): IndexedSeq[A] = {
    val stride = ((rays.size + maxRays - 1) / maxRays).max(1)
    rays.indices.by(stride).map(rays)
  }
}
