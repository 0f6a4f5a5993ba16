package rtaccel.datapath

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayPrepUnit
import rtaccel.fp.{FloatFormat, FpConvert, RoundingMode}
import rtaccel.leaf.{PrimAnswer, PrimIntersect, TriangleRecord}
import rtaccel.traversal.{BoxAnswer, BoxLane}
import rtaccel.{AccelConfig, Datapath, ErrorFlags}

/** The floating-point datapath: per-ray setup, slab test and triangle test
  * in `fmt` on the project's FP units, each unit an II = 1 pipeline whose
  * latency is derived from its FP units' latencies (see [[HwArith]]). Inputs
  * arrive as FP32 and are narrowed in the units (docs/kernels.md; the
  * narrowing rules are in [[RayKernel]], [[BoxKernel]], [[TriangleCommon]]).
  * `cfg.float` must equal `fmt`. Its golden twin is [[FloatGolden]].
  */
final case class FloatDatapath(fmt: FloatFormat, test: TriangleTest, rounding: BoxRounding)
    extends Datapath[RayConsts] {
  require(fmt.expBits <= 8 && fmt.manBits <= 23, s"FloatDatapath: $fmt is wider than FP32 in some field")
  require(fmt.manBits >= 3, s"FloatDatapath: $fmt needs manBits >= 3 (the conservative box bound uses it)")
  val name: String = s"${fmt.name}_${test.tag}_${rounding.tag}"
  def gen: RayConsts = new RayConsts(fmt, test, rounding)
  private def check(cfg: AccelConfig): Unit =
    require(cfg.float == fmt, s"FloatDatapath $name used with AccelConfig.float = ${cfg.float}")

  def rayPrep(cfg: AccelConfig): RayPrepUnit[RayConsts] = { check(cfg); new FloatRayPrep(cfg, this) }
  def box(cfg: AccelConfig): BoxLane[RayConsts] = { check(cfg); new FloatBox(cfg, this) }
  def prim(cfg: AccelConfig): PrimIntersect[RayConsts] = { check(cfg); new FloatPrim(cfg, this) }

  /** Widening is exact, so the mode is irrelevant; a latency-0 converter is wires. */
  def toFloat32(cfg: AccelConfig, x: UInt): UInt =
    if (fmt == FloatFormat.FP32) x
    else {
      val c = Module(new FpConvert(fmt, FloatFormat.FP32, Some(RoundingMode.RNE), latency = 0))
      c.io.in.valid := true.B
      c.io.in.bits.a := x
      c.io.out.bits
    }
}

object FloatDatapath {
  /** Parses names as produced by `name`, e.g. `e8m23_wt_cons`. */
  def parse(s: String): FloatDatapath = s.split('_') match {
    case Array(f, t, r) =>
      FloatDatapath(FloatFormat.parse(f),
        TriangleTest.all.find(_.tag == t).getOrElse(throw new IllegalArgumentException(s"datapath '$s': unknown test '$t'")),
        BoxRounding.all.find(_.tag == r).getOrElse(throw new IllegalArgumentException(s"datapath '$s': unknown rounding '$r'")))
    case _ => throw new IllegalArgumentException(s"not a datapath name: '$s' (expected e.g. e8m23_wt_cons)")
  }
  /** Cycle at which the last of `outs` is ready: the unit's latency. */
  private[datapath] def readyOf(outs: Seq[Timed[_ <: Data]]): Int = outs.filterNot(_.constant).map(_.ready).max
}

class FloatRayPrep(cfg: AccelConfig, dp: FloatDatapath) extends RayPrepUnit[RayConsts](cfg, dp.gen) {
  override def desiredName: String = s"RayPrep_${dp.name}"
  private val ar = new HwArith(dp.fmt)
  private val r = io.in.bits
  private val (k, tmax) = RayKernel(ar, r.origin.map(ar.input), r.dir.map(ar.input), ar.input(r.tmin),
    ar.input(r.tmax), dp.rounding, dp.test)
  private val kernelOuts: Seq[Timed[_ <: Data]] =
    k.o ++ k.d ++ k.rcpLo ++ k.rcpHi ++ Seq(k.tmin, tmax, k.err) ++
      k.shear.toSeq.flatMap(s => s.kx ++ s.ky ++ s.kz ++ Seq(s.sx, s.sy, s.sz))
  private val lat = FloatDatapath.readyOf(kernelOuts)
  def latency: Int = lat
  RayConsts.drive(io.out.bits.statics, k, lat)
  io.out.bits.tmax := tmax.at(lat)
  io.out.bits.dirNeg := VecInit(k.d.map(d => ar.signBit(d).at(lat)))
  io.out.bits.errors := Mux(k.err.at(lat), ErrorFlags.bit(ErrorFlags.InvalidRay), 0.U)
  io.out.valid := ShiftRegister(io.in.valid, lat, false.B, true.B)
}

class FloatBox(cfg: AccelConfig, dp: FloatDatapath) extends BoxLane[RayConsts](cfg, dp.gen) {
  override def desiredName: String = s"BoxLane_${dp.name}"
  private val ar = new HwArith(dp.fmt)
  private val q = io.in.bits
  private val out = BoxKernel(ar, dp.rounding, RayConsts.read(ar, q.ray), ar.input(q.tmax),
    q.boxMin.map(ar.input), q.boxMax.map(ar.input))
  private val lat = FloatDatapath.readyOf(Seq(out.hit, out.near))
  def latency: Int = lat
  io.out.bits.hit := out.hit.at(lat)
  io.out.bits.near := out.near.at(lat)
  io.out.valid := ShiftRegister(io.in.valid, lat, false.B, true.B)
}

class FloatPrim(cfg: AccelConfig, dp: FloatDatapath) extends PrimIntersect[RayConsts](cfg, dp.gen) {
  override def desiredName: String = s"PrimIntersect_${dp.name}"
  private val ar = new HwArith(dp.fmt)
  private val q = io.in.bits
  private val ray = RayConsts.read(ar, q.ray)
  private val verts = for (v <- 0 until 3; a <- 0 until 3) yield ar.input(TriangleRecord.vertexWord(q.triangle, v, a))
  private val out = dp.test match {
    case TriangleTest.Moller     => MollerKernel(ar, ray, ar.input(q.tmax), verts)
    case TriangleTest.Watertight => WatertightKernel(ar, ray, ar.input(q.tmax), verts)
  }
  private val lat = FloatDatapath.readyOf(Seq(out.hit, out.t, out.u, out.v))
  def latency: Int = lat
  io.out.bits.hit := out.hit.at(lat)
  io.out.bits.t := out.t.at(lat)
  io.out.bits.u := out.u.at(lat)
  io.out.bits.v := out.v.at(lat)
  io.out.valid := ShiftRegister(io.in.valid, lat, false.B, true.B)
}
