package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig

/** Test equipment for LeafIntersect's control: a PrimIntersect whose answer is
  * written in the triangle record itself (word 0 = t, word 1 = u, word 2 = v,
  * word 3 bit 0 = "hits"), so a spec can make any pattern of hits, misses and
  * ties. It honours tmax like the real units (hit only if t <= tmax; t is a
  * non-negative FP32, so integer order is float order) and has a real latency.
  * The real units (BboxIntersect, PrimIntersect) have their own specs.
  */
class FieldPrim(cfg: AccelConfig, val latency: Int) extends PrimIntersect[UInt](cfg, UInt(16.W)) {
  private val rec = io.in.bits.triangle
  private val a = Wire(new PrimAnswer(cfg))
  a.t := rec(31, 0)
  a.u := rec(63, 32)
  a.v := rec(95, 64)
  a.hit := rec(96) && rec(31, 0) <= io.in.bits.tmax
  io.out := Pipe(io.in.valid, a, latency)
}
