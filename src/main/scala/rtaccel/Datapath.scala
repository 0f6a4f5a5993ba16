package rtaccel

import chisel3._
import rtaccel.fetch.RayPrepUnit
import rtaccel.leaf.PrimIntersect
import rtaccel.traversal.BoxLane

/** The arithmetic of an accelerator, chosen as a whole: what a ray's
  * per-ray constants are (`gen`), how they are computed once per ray, and the
  * box and triangle units that consume them. The control path (FetchBVH,
  * Traversal, LeafIntersect) is the same for every datapath.
  */
trait Datapath[T <: Data] {
  def name: String
  def gen: T
  def rayPrep(cfg: AccelConfig): RayPrepUnit[T]
  def box(cfg: AccelConfig): BoxLane[T]
  def prim(cfg: AccelConfig): PrimIntersect[T]

  /** A triangle-format value (t, u, v) as FP32; exact, since formats are no wider than FP32. */
  def toFloat32(cfg: AccelConfig, x: UInt): UInt
}
