package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, Datapath}

/** A ray against all `cfg.boxLanes` child boxes of one node. */
class BboxQuery[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val ray = gen.cloneType

  /** In the triangle format: the leaf unit writes it, each lane converts it (FloatBox). */
  val tmax = UInt(cfg.triFloat.width.W)
  val boxMin = Vec(cfg.boxLanes, Vec(3, UInt(32.W)))
  val boxMax = Vec(cfg.boxLanes, Vec(3, UInt(32.W)))

  /** Used slots; an empty slot never hits, whatever its box words hold. */
  val present = Vec(cfg.boxLanes, Bool())
}

class BboxAnswer(cfg: AccelConfig) extends Bundle {

  /** Slot i's box is hit (and the slot is used). */
  val hit = Vec(cfg.boxLanes, Bool())

  /** Slot i's entry distance, in the box format (meaningful where hit); with grid box tests the
    * grid's signed integer relative to the node (GridBboxIntersect), as bits.
    */
  val near = Vec(cfg.boxLanes, UInt(cfg.nearBits.W))

  /** The entry order of each pair of slots (TraversalControl.order). */
  val order = Vec(TraversalControl.pairs(cfg.boxLanes).size, Bool())
}

/** The box test of the traversal loop: one node per cycle, its K child boxes
  * tested side by side by K copies of the datapath's box unit (`BoxIntersect_*`,
  * one lane each), so a node costs one cycle whatever its width (II = 1). The
  * lanes share the ray and its tmax, read once per node from the RayBuffer.
  * The answer comes `latency` cycles later: the lane latency, since every
  * lane is the same pipeline.
  */
class BboxIntersect[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(Valid(new BboxQuery(cfg, dp.gen)))
    val out = Valid(new BboxAnswer(cfg))
  })
  override def desiredName = s"BboxIntersect_k${cfg.boxLanes}_${dp.name}"

  private val lanes = Seq.fill(cfg.boxLanes)(Module(dp.box(cfg)))
  val latency: Int = lanes.head.latency
  for ((lane, i) <- lanes.zipWithIndex) {
    lane.io.in.valid := io.in.valid
    lane.io.in.bits.ray := io.in.bits.ray
    lane.io.in.bits.tmax := io.in.bits.tmax
    lane.io.in.bits.boxMin := io.in.bits.boxMin(i)
    lane.io.in.bits.boxMax := io.in.bits.boxMax(i)
  }
  private val presentReg = BboxIntersect.delayedToRegister(io.in.bits.present, latency)
  io.out.valid := lanes.head.io.out.valid
  for ((lane, i) <- lanes.zipWithIndex) {
    io.out.bits.hit(i) := lane.io.out.bits.hit && presentReg(i)
    io.out.bits.near(i) := lane.io.out.bits.near
  }
  // Compared a cycle before the answer leaves, from each lane's entry distance as it is ready, and registered.
  if (cfg.boxLanes > 1) io.out.bits.order := RegNext(TraversalControl.order(cfg, lanes.map(_.io.nearAhead)))
}

object BboxIntersect {

  /** `x` delayed by `n` >= 1 cycles, free-running, its last stage a register with a reset: the stages before it
    * become a shift-register LUT, and the reset keeps the last one out of it, so the logic that reads the result
    * starts from a flip-flop, not from the SRL's clock-to-out (about a nanosecond longer, docs/fmax.md). */
  def delayedToRegister[T <: Data](x: T, n: Int): T = {
    require(n >= 1, s"BboxIntersect.delayedToRegister: a delay of $n cycles")
    RegNext(ShiftRegister(x, n - 1), 0.U.asTypeOf(x))
  }
}
