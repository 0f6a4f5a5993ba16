package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.datapath.RayConsts

/** The box test of a quantized node in the node's own grid: one
  * [[GridNodeStage]] per node (FP32, shared by the K children) and K
  * [[GridLane]]s (integers), one node per cycle (II = 1). Takes the node's
  * per-axis origin and scale exponent and each child's plane offsets as the
  * 4q/8q record holds them (QuantNode); answers per child hit and an entry
  * order key, `latency` cycles later. No child box the ray enters is missed
  * (docs/kernels.md, "Box tests in the node's grid").
  */
class GridBboxIntersect(k: Int, p: GridParams, rays: RayConsts) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(Valid(new Bundle {
      val node = new GridNodeIn(rays)
      val children = Vec(k, new GridChildHw(p))
    }))
    val out = Valid(new Bundle {
      val hit = Vec(k, Bool())

      /** Entry distance relative to the node, in its unit: orders the children, nothing more. */
      val near = Vec(k, SInt(p.width.W))

      /** Bad scale exponent: the node is bad scene data (no hits). */
      val badScale = Bool()
    })
  })
  override def desiredName = s"GridBboxIntersect_k${k}_${p.name}"

  private val stage = Module(new GridNodeStage(p, rays))
  stage.io.in.valid := io.in.valid
  stage.io.in.bits := io.in.bits.node
  // The children wait for their node's constants, loading only on valid slots.
  private val children = (0 until stage.latency).foldLeft((io.in.bits.children, io.in.valid)) { case ((c, v), _) =>
    (RegEnable(c, v), RegNext(v, false.B))
  }._1
  private val lanes = Seq.fill(k)(Module(new GridLane(p)))
  val latency: Int = stage.latency + lanes.head.latency
  for ((lane, i) <- lanes.zipWithIndex) {
    lane.io.in.valid := stage.io.out.valid
    lane.io.in.bits.node := stage.io.out.bits
    lane.io.in.bits.child := children(i)
  }
  private val badReg = BboxIntersect.delayedToRegister(stage.io.badScale, lanes.head.latency)
  io.out.valid := lanes.head.io.outValid
  for ((lane, i) <- lanes.zipWithIndex) {
    io.out.bits.hit(i) := lane.io.hit && !badReg
    io.out.bits.near(i) := lane.io.near
  }
  io.out.bits.badScale := badReg
}
