package rtaccel.datapath

import chisel3._
import rtaccel.fp.FloatFormat

/** A ray's per-ray constants as a hardware bundle (the `statics` of
  * [[rtaccel.fetch.PreparedRay]]): the fields of [[RayK]], in `fmt`. The
  * conservative upper reciprocals exist only in Conservative mode, the shear
  * only for the watertight test, so a datapath carries what it uses.
  */
class RayConsts(val fmt: FloatFormat, val test: TriangleTest, val rounding: BoxRounding) extends Bundle {
  private def f = UInt(fmt.width.W)
  val origin = Vec(3, f)
  val dir    = Vec(3, f)
  val tmin   = f
  val err    = Bool()
  val rcpLo  = Vec(3, f)
  val rcpHi  = Option.when(rounding == BoxRounding.Conservative)(Vec(3, f))
  /** One-hot kx, ky, kz. */
  val axes   = Option.when(test == TriangleTest.Watertight)(Vec(3, Vec(3, Bool())))
  /** Sx, Sy, Sz. */
  val shear  = Option.when(test == TriangleTest.Watertight)(Vec(3, f))
}

object RayConsts {
  /** Drives `b` from a computed ray, every field at `cycle`. */
  def drive(b: RayConsts, k: RayK[Timed[UInt], Timed[Bool]], cycle: Int): Unit = {
    def at(xs: Seq[Timed[UInt]]) = VecInit(xs.map(_.at(cycle)))
    b.origin := at(k.o)
    b.dir := at(k.d)
    b.tmin := k.tmin.at(cycle)
    b.err := k.err.at(cycle)
    b.rcpLo := at(k.rcpLo)
    b.rcpHi.foreach(_ := at(k.rcpHi))
    for (s <- k.shear; ax <- b.axes; sh <- b.shear) {
      ax := VecInit(Seq(s.kx, s.ky, s.kz).map(v => VecInit(v.map(_.at(cycle)))))
      sh := at(Seq(s.sx, s.sy, s.sz))
    }
  }

  /** The constants as kernel inputs valid at cycle 0. */
  def read(ar: HwArith, b: RayConsts): RayK[Timed[UInt], Timed[Bool]] = {
    val lo = b.rcpLo.map(ar.input)
    val shear = for (ax <- b.axes; sh <- b.shear) yield {
      val Seq(kx, ky, kz) = ax.map(_.map(ar.inputB))
      Shear(kx, ky, kz, ar.input(sh(0)), ar.input(sh(1)), ar.input(sh(2)))
    }
    RayK(b.origin.map(ar.input), b.dir.map(ar.input), ar.input(b.tmin), ar.inputB(b.err), lo,
      b.rcpHi.map(_.map(ar.input)).getOrElse(lo), shear)
  }
}
