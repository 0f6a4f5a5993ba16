package rtaccel.sim

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayPrepUnit
import rtaccel.fp.FloatFormat
import rtaccel.golden.{ArithGolden, PreparedGolden, RayRecord}
import rtaccel.leaf.{PrimAnswer, PrimIntersect}
import rtaccel.scene.{NodeRecord, TriangleRecord}
import rtaccel.traversal.{BoxAnswer, BoxLane}
import rtaccel.{AccelConfig, Datapath, ErrorFlags}

/** Test equipment for the control path: a datapath whose "geometry" is a hash
  * of the ray's key and the record's fields, cheap to build and simulate, with
  * a bit-exact Scala twin. It keeps what matters to control: box hits that
  * depend on the ray, culling by the current tmax (so the tmax written at leaf
  * exit must be seen by the next box test), hits with ties in t, real
  * latencies, and InvalidRay on NaN/inf input. FP32 format, positive t only.
  */
object FieldDatapath extends Datapath[UInt] {
  val name = "field"
  def gen: UInt = UInt(16.W)
  val prepLatency = 3
  val boxLatency = 4
  val primLatency = 5

  private def mix(key: UInt, w: UInt): UInt = ((key ^ w(15, 0) ^ w(31, 16)) * 0x9e37.U)(15, 0)

  def rayPrep(cfg: AccelConfig): RayPrepUnit[UInt] = new RayPrepUnit[UInt](cfg, gen) {
    def latency: Int = prepLatency
    private val r = io.in.bits
    private val p = Wire(chiselTypeOf(io.out.bits))
    p.statics := r.origin(0)(15, 0)
    p.tmax := r.tmax
    p.dirNeg := VecInit(r.dir.map(_(31)))
    p.errors := Mux(
      (r.origin ++ r.dir).map(ErrorFlags.nonFinite).reduce(_ || _),
      ErrorFlags.bit(ErrorFlags.InvalidRay),
      0.U
    )
    io.out := Pipe(io.in.valid, p, latency)
  }

  def box(cfg: AccelConfig): BoxLane[UInt] = new BoxLane[UInt](cfg, gen) {
    def latency: Int = boxLatency
    private val q = io.in.bits
    private val a = Wire(new BoxAnswer(this.cfg))
    private val m = mix(q.ray, q.boxMin(0))
    a.hit := (m(15) || m(14)) && q.boxMin(1) <= q.tmax
    a.near := q.boxMin(1)
    io.out := Pipe(io.in.valid, a, latency)
    io.nearAhead := Pipe(io.in.valid, a, latency - 1).bits.near
  }

  def prim(cfg: AccelConfig): PrimIntersect[UInt] = new PrimIntersect[UInt](cfg, gen) {
    def latency: Int = primLatency
    private val rec = io.in.bits.triangle
    private val a = Wire(new PrimAnswer(this.cfg))
    a.t := rec(31, 0)
    a.u := rec(63, 32)
    a.v := rec(95, 64)
    a.hit := mix(io.in.bits.ray, rec(127, 96))(15) && rec(31, 0) <= io.in.bits.tmax
    io.out := Pipe(io.in.valid, a, latency)
  }

  def toFloat32(cfg: AccelConfig, x: UInt): UInt = x

  /** The bit-exact Scala twin. */
  object Golden extends ArithGolden[Int] {
    def boxFormat: FloatFormat = FloatFormat.FP32
    def triFormat: FloatFormat = FloatFormat.FP32
    private def mix(key: Int, w: Long): Int = (((key ^ (w & 0xffff) ^ ((w >> 16) & 0xffff)) * 0x9e37) & 0xffff).toInt
    def prep(r: RayRecord): PreparedGolden[Int] =
      PreparedGolden(
        (r.origin(0) & 0xffff).toInt,
        BigInt(r.tmax),
        r.dir.map(d => ((d >> 31) & 1) == 1),
        if ((r.origin ++ r.dir).exists(ErrorFlags.nonFiniteWord)) 1 << ErrorFlags.InvalidRay else 0
      )
    def box(s: Int, tmax: BigInt, n: NodeRecord): (Boolean, BigInt) = {
      val m = mix(s, n.boxMin(0))
      (((m >> 15) & 1) + ((m >> 14) & 1) > 0 && BigInt(n.boxMin(1)) <= tmax, BigInt(n.boxMin(1)))
    }
    def prim(s: Int, tmax: BigInt, tri: TriangleRecord): Option[(BigInt, BigInt, BigInt)] = {
      val w = tri.vertexWords
      if (((mix(s, w(3)) >> 15) & 1) == 1 && BigInt(w(0)) <= tmax) Some((BigInt(w(0)), BigInt(w(1)), BigInt(w(2))))
      else None
    }
    def toFloat32(x: BigInt): Long = x.toLong
  }
}
