package rtaccel.datapath

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayPrepUnit
import rtaccel.fp.{FloatFormat, FpConvert, RoundingMode}
import rtaccel.leaf.{PrimAnswer, PrimIntersect, TriangleRecord}
import rtaccel.traversal.{BoxAnswer, BoxLane}
import rtaccel.{AccelConfig, Datapath, ErrorFlags}

/** The floating-point datapath: per-ray setup, slab test and triangle test
  * on the project's FP units, each unit an II = 1 pipeline whose latency is
  * derived from its FP units' latencies (see [[HwArith]]). The box lanes work
  * in `boxFmt`, the triangle test in `triFmt` (one format for both is the
  * `FLOAT=` shorthand, `apply(fmt, test, rounding)`); the ray setup follows
  * the unit it feeds ([[RayKernel.split]]), and the ray's tmax is kept in
  * `triFmt` and narrowed by each box lane ([[BoxKernel.narrowTmax]]). Inputs
  * arrive as FP32 and are narrowed in the units (docs/kernels.md; the
  * narrowing rules are in [[RayKernel]], [[BoxKernel]], [[TriangleCommon]]).
  * The config's `boxFloat`/`triFloat` must equal them. Its golden twin is [[FloatGolden]].
  */
final case class FloatDatapath(boxFmt: FloatFormat, triFmt: FloatFormat, test: TriangleTest, rounding: BoxRounding)
    extends Datapath[RayConsts] {
  for (f <- Seq(boxFmt, triFmt)) {
    require(f.expBits <= 8 && f.manBits <= 23, s"FloatDatapath: $f is wider than FP32 in some field")
    require(f.manBits >= 3, s"FloatDatapath: $f needs manBits >= 3 (the conservative box bound uses it)")
  }

  /** `e8m23_wt_cons`; split formats name the box format first: `e8m10e8m23_wt_cons`. */
  val name: String = s"${FloatDatapath.formatsName(boxFmt, triFmt)}_${test.tag}_${rounding.tag}"

  /** The one format of a single-format datapath (tests and tools that build one). */
  def fmt: FloatFormat = {
    require(boxFmt == triFmt, s"FloatDatapath $name: box and triangle formats differ; ask for boxFmt or triFmt")
    boxFmt
  }
  def split: Boolean = boxFmt != triFmt
  def gen: RayConsts = new RayConsts(boxFmt, triFmt, test, rounding)

  /** `cfg` with this datapath's formats. */
  def configure(cfg: AccelConfig): AccelConfig = cfg.copy(boxFloat = boxFmt, triFloat = triFmt)
  private def check(cfg: AccelConfig): Unit =
    require(
      cfg.boxFloat == boxFmt && cfg.triFloat == triFmt,
      s"FloatDatapath $name used with AccelConfig formats box ${cfg.boxFloat}, triangle ${cfg.triFloat}"
    )

  def rayPrep(cfg: AccelConfig): RayPrepUnit[RayConsts] = { check(cfg); new FloatRayPrep(cfg, this) }
  def box(cfg: AccelConfig): BoxLane[RayConsts] = { check(cfg); new FloatBox(cfg, this) }
  def prim(cfg: AccelConfig): PrimIntersect[RayConsts] = { check(cfg); new FloatPrim(cfg, this) }

  /** The grid box unit of `cfg` (BoxTest.Grid: its FP32 node stage and `cfg.boxLanes` grid lanes). */
  def gridBox(cfg: AccelConfig): rtaccel.traversal.GridBboxIntersect = {
    check(cfg); new rtaccel.traversal.GridBboxIntersect(cfg.boxLanes, cfg.gridParams, gen)
  }

  /** A triangle-format value (t, u, v) as FP32. Widening is exact, so the mode
    * is irrelevant; a latency-0 converter is wires.
    */
  def toFloat32(cfg: AccelConfig, x: UInt): UInt =
    if (triFmt == FloatFormat.FP32) x
    else {
      val c = Module(new FpConvert(triFmt, FloatFormat.FP32, Some(RoundingMode.RNE), latency = 0))
      c.io.in.valid := true.B
      c.io.in.bits.a := x
      c.io.out.bits
    }
}

object FloatDatapath {

  /** One format for both units: the `FLOAT=` shorthand. */
  def apply(fmt: FloatFormat, test: TriangleTest, rounding: BoxRounding): FloatDatapath =
    FloatDatapath(fmt, fmt, test, rounding)

  /** The datapath of `cfg`'s formats. */
  def of(cfg: AccelConfig, test: TriangleTest, rounding: BoxRounding): FloatDatapath =
    FloatDatapath(cfg.boxFloat, cfg.triFloat, test, rounding)
  def formatsName(box: FloatFormat, tri: FloatFormat): String = if (box == tri) box.name else s"${box.name}${tri.name}"

  private val Name = """e(\d+)m(\d+)(?:e(\d+)m(\d+))?""".r

  /** Parses names as produced by `name`, e.g. `e8m23_wt_cons` or `e8m10e8m23_wt_cons`. */
  def parse(s: String): FloatDatapath = s.split('_') match {
    case Array(f, t, r) =>
      val (box, tri) = f match {
        case Name(e, m, null, null) => val x = FloatFormat(e.toInt, m.toInt); (x, x)
        case Name(e, m, e2, m2)     => (FloatFormat(e.toInt, m.toInt), FloatFormat(e2.toInt, m2.toInt))
        case _ => throw new IllegalArgumentException(s"datapath '$s': not a format '$f' (expected e8m23 or e8m10e8m23)")
      }
      FloatDatapath(
        box,
        tri,
        TriangleTest.all.find(_.tag == t).getOrElse(throw new IllegalArgumentException(
          s"datapath '$s': unknown test '$t'"
        )),
        BoxRounding.all.find(_.tag == r).getOrElse(throw new IllegalArgumentException(
          s"datapath '$s': unknown rounding '$r'"
        ))
      )
    case _ => throw new IllegalArgumentException(s"not a datapath name: '$s' (expected e.g. e8m23_wt_cons)")
  }

  /** Cycle at which the last of `outs` is ready: the unit's latency. */
  private[datapath] def readyOf(outs: Seq[Timed[_ <: Data]]): Int = outs.filterNot(_.constant).map(_.ready).max
}

class FloatRayPrep(cfg: AccelConfig, dp: FloatDatapath) extends RayPrepUnit[RayConsts](cfg, dp.gen) with ValidChains {
  override def desiredName: String = s"RayPrep_${dp.name}"
  // One pipeline: both arithmetics' units and delays follow the one valid chain.
  private val valid = validChain(io.in.valid)
  private val boxAr = new HwArith(dp.boxFmt, valid)
  // One arithmetic for both when the formats agree: the setup is shared, built once.
  private val triAr = if (dp.split) new HwArith(dp.triFmt, valid) else boxAr
  private val r = io.in.bits
  private val (k, tmax, err) = RayKernel.split(
    boxAr,
    triAr,
    r.origin.map(boxAr.input),
    r.dir.map(boxAr.input),
    boxAr.input(r.tmin),
    boxAr.input(r.tmax),
    dp.rounding,
    dp.test
  )
  private def outs(x: RayK[Timed[UInt], Timed[Bool]]): Seq[Timed[_ <: Data]] =
    x.o ++ x.oHi.toSeq.flatten ++ x.d ++ x.rcpLo ++ x.rcpHi ++ Seq(x.tmin, x.err) ++
      x.shear.toSeq.flatMap(s => s.kx ++ s.ky ++ s.kz ++ Seq(s.sx, s.sy, s.sz))
  private val lat = FloatDatapath.readyOf(outs(k.box) ++ outs(k.tri) ++ Seq(tmax, err))
  def latency: Int = lat
  RayConsts.drive(io.out.bits.statics, k, lat)
  io.out.bits.tmax := tmax.at(lat)
  // The traversal order follows the box lanes' direction (RNE-narrowed, so its sign is FP32's).
  io.out.bits.dirNeg := VecInit(k.box.d.map(d => boxAr.signBit(d).at(lat)))
  io.out.bits.errors := Mux(err.at(lat), ErrorFlags.bit(ErrorFlags.InvalidRay), 0.U)
  io.out.valid := valid.at(lat)
}

class FloatBox(cfg: AccelConfig, dp: FloatDatapath) extends BoxLane[RayConsts](cfg, dp.gen) with ValidChains {
  override def desiredName: String = s"BoxLane_${dp.name}"
  private val ar = new HwArith(dp.boxFmt, validChain(io.in.valid))
  private val q = io.in.bits
  private val out = BoxKernel(
    ar,
    dp.rounding,
    RayConsts.readBox(ar, q.ray),
    BoxKernel.narrowTmax(ar, dp.rounding, ar.input(q.tmax), dp.triFmt),
    q.boxMin.map(ar.input),
    q.boxMax.map(ar.input)
  )
  private val lat = FloatDatapath.readyOf(Seq(out.hit, out.near))
  def latency: Int = lat
  io.out.bits.hit := out.hit.at(lat)
  io.out.bits.near := out.near.at(lat)
  io.out.valid := ar.valid.at(lat)
  // The hit compares the entry distance, so it is ready at least a cycle before the answer.
  require(out.near.ready < lat, s"FloatBox: entry distance ready at ${out.near.ready}, answer at $lat")
  io.nearAhead := out.near.at(lat - 1)
}

class FloatPrim(cfg: AccelConfig, dp: FloatDatapath) extends PrimIntersect[RayConsts](cfg, dp.gen) with ValidChains {
  override def desiredName: String = s"PrimIntersect_${dp.name}"
  private val ar = new HwArith(dp.triFmt, validChain(io.in.valid))
  private val q = io.in.bits
  private val ray = RayConsts.readTri(ar, q.ray)
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
  io.out.valid := ar.valid.at(lat)
}
