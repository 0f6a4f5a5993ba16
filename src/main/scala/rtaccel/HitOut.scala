package rtaccel

import chisel3._

/** One answer per ray, in the order rays finish (not the order they came).
  * `number` is the host's ray number. On a miss `hit` is false and t/u/v/prim
  * are zero. A ray with any error bit set reports no hit: the hardware never
  * returns a hit it could not finish computing. For shadow rays `hit` means
  * "occluded"; t/u/v/prim then describe the first occluder found.
  * t, u, v are FP32 (widened exactly from the datapath format).
  */
class HitOut(cfg: AccelConfig) extends Bundle {
  val number = UInt(32.W)
  val hit = Bool()
  val t = UInt(32.W)
  val u = UInt(32.W)
  val v = UInt(32.W)
  val prim = UInt(cfg.triIndexBits.W)
  val errors = ErrorFlags()
}

/** Event counts for the regression's report. All count cycles or events since reset. */
class PerfCounters extends Bundle {
  val cycles = UInt(64.W)
  val raysIn = UInt(64.W)
  val hitsOut = UInt(64.W)
  val nodeFetches = UInt(64.W)
  val triFetches = UInt(64.W)

  /** Nodes tested by BboxIntersect (all of a node's child boxes at once). */
  val boxTests = UInt(64.W)

  /** Used child boxes among them (boxTests in the nori layout). */
  val childBoxTests = UInt(64.W)
  val triTests = UInt(64.W)
  val decisions = UInt(64.W)

  /** Decisions for rays back from a leaf (a pop that costs a decision of its own). */
  val leafReturns = UInt(64.W)

  /** Cycles a unit wanted to move and could not. */
  val nodePortStall = UInt(64.W)
  val triPortStall = UInt(64.W)
  val raysInStall = UInt(64.W)
  val hitsOutStall = UInt(64.W)

  /** Sum over cycles of the rays in flight (mean = this / cycles). */
  val inFlightSum = UInt(64.W)
}
