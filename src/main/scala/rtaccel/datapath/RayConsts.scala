package rtaccel.datapath

import chisel3._
import rtaccel.fp.FloatFormat

/** One unit's share of a ray's constants, in `fmt`: the fields of [[RayK]]
  * it reads. The reciprocals exist only where a box lane reads them (the
  * upper ones only in Conservative mode), the shear only where a watertight
  * triangle test does, so a datapath carries what it uses.
  */
class RayConstsPart(
    val fmt: FloatFormat,
    rcp: Boolean,
    rcpUpper: Boolean,
    withShear: Boolean,
    originBounds: Boolean = false
) extends Bundle {
  private def f = UInt(fmt.width.W)
  val origin = Vec(3, f)

  /** Upper origin bound ([[RayK.oHi]]): split Conservative box constants only. */
  val originHi = Option.when(originBounds)(Vec(3, f))
  val dir = Vec(3, f)
  val tmin = f
  val err = Bool()
  val rcpLo = Option.when(rcp)(Vec(3, f))
  val rcpHi = Option.when(rcp && rcpUpper)(Vec(3, f))

  /** One-hot kx, ky, kz. */
  val axes = Option.when(withShear)(Vec(3, Vec(3, Bool())))

  /** Sx, Sy, Sz. */
  val shear = Option.when(withShear)(Vec(3, f))
}

/** A ray's per-ray constants as a hardware bundle (the `statics` of
  * [[rtaccel.fetch.PreparedRay]]), the hardware form of [[SplitRay]]. With one
  * format for both units there is one part, `box`, read by both; with split
  * formats `box` is in the box format (no shear) and `tri` in the triangle
  * format (no reciprocals).
  */
class RayConsts(val boxFmt: FloatFormat, val triFmt: FloatFormat, val test: TriangleTest, val rounding: BoxRounding)
    extends Bundle {
  private val shared = boxFmt == triFmt
  private val cons = rounding == BoxRounding.Conservative
  private val wt = test == TriangleTest.Watertight
  val box =
    new RayConstsPart(boxFmt, rcp = true, rcpUpper = cons, withShear = shared && wt, originBounds = !shared && cons)
  val tri = Option.when(!shared)(new RayConstsPart(triFmt, rcp = false, rcpUpper = false, withShear = wt))
}

object RayConsts {

  /** Drives `b` from a computed ray, every field at `cycle`. */
  def drive(b: RayConsts, k: SplitRay[Timed[UInt], Timed[Bool]], cycle: Int): Unit = {
    drivePart(b.box, k.box, cycle)
    b.tri.foreach(drivePart(_, k.tri, cycle))
  }

  private def drivePart(b: RayConstsPart, k: RayK[Timed[UInt], Timed[Bool]], cycle: Int): Unit = {
    def at(xs: Seq[Timed[UInt]]) = VecInit(xs.map(_.at(cycle)))
    b.origin := at(k.o)
    for (hi <- b.originHi)
      hi := at(k.oHi.getOrElse(throw new IllegalArgumentException("RayConsts: originHi without bounds")))
    b.dir := at(k.d)
    b.tmin := k.tmin.at(cycle)
    b.err := k.err.at(cycle)
    b.rcpLo.foreach(_ := at(k.rcpLo))
    b.rcpHi.foreach(_ := at(k.rcpHi))
    for (s <- k.shear; ax <- b.axes; sh <- b.shear) {
      ax := VecInit(Seq(s.kx, s.ky, s.kz).map(v => VecInit(v.map(_.at(cycle)))))
      sh := at(Seq(s.sx, s.sy, s.sz))
    }
  }

  /** The box lanes' constants as kernel inputs valid at cycle 0 (`ar` in the box format). */
  def readBox(ar: HwArith, b: RayConsts): RayK[Timed[UInt], Timed[Bool]] = readPart(ar, b.box)

  /** The triangle unit's constants as kernel inputs valid at cycle 0 (`ar` in the triangle format). */
  def readTri(ar: HwArith, b: RayConsts): RayK[Timed[UInt], Timed[Bool]] = readPart(ar, b.tri.getOrElse(b.box))

  private def readPart(ar: HwArith, b: RayConstsPart): RayK[Timed[UInt], Timed[Bool]] = {
    require(ar.fmt == b.fmt, s"RayConsts: a ${b.fmt} part read in ${ar.fmt}")
    val lo = b.rcpLo.toSeq.flatMap(_.map(ar.input))
    val shear = for (ax <- b.axes; sh <- b.shear) yield {
      val Seq(kx, ky, kz) = ax.map(_.map(ar.inputB))
      Shear(kx, ky, kz, ar.input(sh(0)), ar.input(sh(1)), ar.input(sh(2)))
    }
    RayK(
      b.origin.map(ar.input),
      b.dir.map(ar.input),
      ar.input(b.tmin),
      ar.inputB(b.err),
      lo,
      b.rcpHi.map(_.map(ar.input).toSeq).getOrElse(lo),
      shear,
      b.originHi.map(_.map(ar.input).toSeq)
    )
  }
}
