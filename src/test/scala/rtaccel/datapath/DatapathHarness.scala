package rtaccel.datapath

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ErrorFlags}
import rtaccel.leaf.TriangleRecord

/** Test wrapper around one datapath's three units, two lanes per cycle:
  * lane A = ray prep then box, lane B = ray prep then triangle, so one
  * Verilator build runs a box case and a triangle case every cycle. Inputs
  * and outputs are packed into a few wide words (one poke/peek each), FP32
  * words at [32i+31 : 32i] in vector-file order. Both answers come out
  * `latency` cycles after the inputs.
  */
class DatapathHarness(val dp: FloatDatapath) extends Module {
  val cfg = AccelConfig(boxFloat = dp.boxFmt, triFloat = dp.triFmt)
  private val (bw, tw) = (dp.boxFmt.width, dp.triFmt.width)
  val io = IO(new Bundle {
    val valid = Input(Bool())
    val boxRay = Input(UInt(256.W)) // o, d, tmin, tmax
    val box = Input(UInt(192.W)) // bmin, bmax
    val triRay = Input(UInt(256.W))
    val tri = Input(UInt(288.W)) // p0, p1, p2
    val outValid = Output(Bool())

    /** err, hit, near (near in the low box-format bits). */
    val boxOut = Output(UInt((bw + 2).W))

    /** err, hit, t, u, v (v in the low triangle-format bits). */
    val primOut = Output(UInt((3 * tw + 2).W))
  })
  private def words(x: UInt, n: Int) = VecInit((0 until n).map(i => x(32 * i + 31, 32 * i)))
  private def prep(ray: UInt) = RayPrepFromWords(dp, cfg, io.valid, words(ray, 8))
  private val prepA = prep(io.boxRay)
  private val prepB = prep(io.triRay)
  val prepLatency: Int = prepA.latency

  private val box = Module(dp.box(cfg))
  private val bounds = words(ShiftRegister(io.box, prepLatency), 6)
  box.io.in.valid := prepA.io.out.valid
  box.io.in.bits.ray := prepA.io.out.bits.statics
  box.io.in.bits.tmax := prepA.io.out.bits.tmax
  box.io.in.bits.boxMin := VecInit(bounds.slice(0, 3))
  box.io.in.bits.boxMax := VecInit(bounds.slice(3, 6))

  private val prim = Module(dp.prim(cfg))
  prim.io.in.valid := prepB.io.out.valid
  prim.io.in.bits.ray := prepB.io.out.bits.statics
  prim.io.in.bits.tmax := prepB.io.out.bits.tmax
  prim.io.in.bits.triangle := ShiftRegister(io.tri, prepLatency).pad(TriangleRecord.RecordBytes * 8)

  val boxLatency: Int = box.latency
  val primLatency: Int = prim.latency
  val latency: Int = prepLatency + (boxLatency max primLatency)
  private def invalid(p: rtaccel.fetch.RayPrepUnit[RayConsts]) = p.io.out.bits.errors(ErrorFlags.InvalidRay)
  private val boxErr = ShiftRegister(invalid(prepA), boxLatency)
  private val primErr = ShiftRegister(invalid(prepB), primLatency)
  io.boxOut := ShiftRegister(Cat(boxErr, box.io.out.bits.hit, box.io.out.bits.near), latency - prepLatency - boxLatency)
  io.primOut := ShiftRegister(
    Cat(primErr, prim.io.out.bits.hit, prim.io.out.bits.t, prim.io.out.bits.u, prim.io.out.bits.v),
    latency - prepLatency - primLatency
  )
  io.outValid := ShiftRegister(io.valid, latency, false.B, true.B)
}

/** A datapath's RayPrep driven by eight FP32 words (o, d, tmin, tmax), for unit harnesses. */
object RayPrepFromWords {
  def apply(dp: FloatDatapath, cfg: AccelConfig, valid: Bool, r: Seq[UInt]): rtaccel.fetch.RayPrepUnit[RayConsts] = {
    val p = Module(dp.rayPrep(cfg))
    p.io.in.valid := valid
    p.io.in.bits.origin := VecInit(r.slice(0, 3))
    p.io.in.bits.dir := VecInit(r.slice(3, 6))
    p.io.in.bits.tmin := r(6)
    p.io.in.bits.tmax := r(7)
    p
  }
}
