package rtaccel.leaf

import chisel3._
import rtaccel.traversal.TraversalToken
import rtaccel.{AccelConfig, ErrorFlags}

/** A LeafIntersect exit as it is registered before the exit queue: the token (a block RAM read, the parked
  * table) and the flags to combine with it after the register ([[queued]]). Combined before it, the token's read
  * ran through the flags' ORs and the select of the two exits into the queue's write data (6.00 ns,
  * docs/fmax.md).
  */
class ExitParts(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)
  val errors = UInt(ErrorFlags.width.W)
  val occluded = Bool()
  val answeredHit = Bool() // the last answer hit: the exit is occluded if the ray is a shadow ray
  val hit = Bool()

  /** The exit queue's entry. */
  def queued: QueuedExit = {
    val q = Wire(new QueuedExit(cfg))
    q.exit.token := token
    q.exit.token.errors := token.errors | errors
    q.exit.occluded := occluded || (answeredHit && token.shadow)
    q.hasHit := hit
    q
  }
}
