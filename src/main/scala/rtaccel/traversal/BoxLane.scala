package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig

/** A ray against one node's box. The box comes raw from memory (FP32); the
  * unit narrows it to its format (outward, in conservative mode).
  */
class BoxQuery[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val ray = gen.cloneType

  /** The ray's tmax in the triangle format (the leaf unit writes it); the lane narrows it. */
  val tmax = UInt(cfg.triFloat.width.W)
  val boxMin = Vec(3, UInt(32.W))
  val boxMax = Vec(3, UInt(32.W))
}

class BoxAnswer(cfg: AccelConfig) extends Bundle {
  val hit = Bool()

  /** Entry distance, in the box format. */
  val near = UInt(cfg.boxFloat.width.W)
}

/** One lane of BboxIntersect: one box test per cycle in, the answer
  * `latency` cycles later (II = 1). A datapath supplies it; BboxIntersect
  * instantiates one per child slot.
  */
abstract class BoxLane[T <: Data](val cfg: AccelConfig, val gen: T) extends Module {
  def latency: Int
  val io = IO(new Bundle {
    val in = Flipped(Valid(new BoxQuery(cfg, gen)))
    val out = Valid(new BoxAnswer(cfg))

    /** The entry distance of the answer that leaves next cycle (BboxIntersect orders the children on it). */
    val nearAhead = Output(UInt(cfg.boxFloat.width.W))
  })
}
