package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayPrepUnit
import rtaccel.leaf.PrimIntersect
import rtaccel.traversal.BoxLane
import rtaccel.{AccelConfig, Datapath}

/** A datapath for the proofs: every result (a ray's constants, tmax, signs
  * and error bits; each box's hit and entry distance; each triangle's hit,
  * t, u, v) is a free value the model checker chooses, so a property proved
  * with it holds whatever the arithmetic answers. Only the latencies are
  * real: the control path depends on them.
  */
class FormalDatapath(val prepLatency: Int, val boxLatency: Int, val primLatency: Int) extends Datapath[UInt] {
  require(Seq(prepLatency, boxLatency, primLatency).forall(_ >= 1), "FormalDatapath: latencies must be >= 1")
  val name = s"formal_p${prepLatency}b${boxLatency}t$primLatency"

  /** A ray's constants do not matter: one bit. */
  def gen: UInt = UInt(1.W)

  def rayPrep(cfg: AccelConfig): RayPrepUnit[UInt] = new RayPrepUnit[UInt](cfg, gen) {
    def latency: Int = prepLatency
    io.out := Pipe(io.in.valid, FormalAnySeq(chiselTypeOf(io.out.bits)), latency)
  }
  def box(cfg: AccelConfig): BoxLane[UInt] = new BoxLane[UInt](cfg, gen) {
    def latency: Int = boxLatency
    io.out := Pipe(io.in.valid, FormalAnySeq(chiselTypeOf(io.out.bits)), latency)
    // Any entry distances: the children's order is the solver's choice too.
    io.nearAhead := FormalAnySeq(chiselTypeOf(io.nearAhead))
  }
  def prim(cfg: AccelConfig): PrimIntersect[UInt] = new PrimIntersect[UInt](cfg, gen) {
    def latency: Int = primLatency
    io.out := Pipe(io.in.valid, FormalAnySeq(chiselTypeOf(io.out.bits)), latency)
  }
  def toFloat32(cfg: AccelConfig, x: UInt): UInt = x.pad(32)
}
