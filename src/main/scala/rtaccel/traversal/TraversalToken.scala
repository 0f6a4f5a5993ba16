package rtaccel.traversal

import chisel3._
import rtaccel.{AccelConfig, ErrorFlags}

/** What travels with a ray ID around the traversal loop. Everything larger
  * stays in per-ray memories indexed by `rayId` (docs/architecture.md).
  */
class TraversalToken(cfg: AccelConfig) extends Bundle {
  val rayId = UInt(cfg.rayIdBits.W)

  /** The node the ray is at: tested next, or just tested. */
  val nodeIdx = UInt(cfg.nodeIndexBits.W)

  /** Number of entries on the ray's stack. */
  val sp = UInt(cfg.stackPtrBits.W)

  /** Direction sign per axis (true = negative): picks the near child. */
  val dirNeg = Vec(3, Bool())

  /** Any-hit (occlusion) ray: stops at its first hit. */
  val shadow = Bool()
  val errors = ErrorFlags()
}
