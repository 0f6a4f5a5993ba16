package rtaccel.leaf

import chisel3._
import rtaccel.traversal.TraversalToken
import rtaccel.AccelConfig

class LeafJob(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)
  val first = UInt(cfg.triIndexBits.W)
  val count = UInt(cfg.leafCountBits.W)
}

class LeafExit(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)

  /** A shadow ray found an occluder: its traversal is over. */
  val occluded = Bool()
}

/** An exit as LeafIntersect queues it: with whether the ray holds a hit, so
  * that the exit's tmax write and its handshake read no 1-of-`numRayIds` table.
  */
class QueuedExit(cfg: AccelConfig) extends Bundle {
  val exit = new LeafExit(cfg)
  val hasHit = Bool()
}

class BestHit(cfg: AccelConfig) extends Bundle {
  val t = UInt(cfg.triFloat.width.W)
  val u = UInt(cfg.triFloat.width.W)
  val v = UInt(cfg.triFloat.width.W)
  val prim = UInt(cfg.triIndexBits.W)
}

/** A write to the best-hit table: ray `id`'s new best hit. */
class BestWrite(cfg: AccelConfig) extends Bundle {
  val id = UInt(cfg.rayIdBits.W)
  val hit = new BestHit(cfg)
}

/** What travels beside an answer through the triangle test: its ray, its triangle's index word, and whether a
  * vertex word is NaN or infinite (the scene in memory is bad).
  */
class AnswerCarry(cfg: AccelConfig) extends Bundle {
  val rayId = UInt(cfg.rayIdBits.W)
  val prim = UInt(32.W)
  val bad = Bool()
}
