package rtaccel.regress

import chisel3.Data
import rtaccel.Datapath
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.golden.ArithGolden
import rtaccel.sim.FieldDatapath

/** A datapath and its golden model, which must agree bit for bit. */
final case class Chosen[T <: Data, S](dp: Datapath[T], golden: ArithGolden[S])

object DatapathChoice {

  /** Resolves `make regress` FLOAT / TRIANGLE / ROUNDING to a datapath.
    * FLOAT=field selects the control-path test datapath (no real geometry).
    */
  def resolve(float: String, triangle: String, rounding: String): Chosen[_ <: Data, _] =
    resolve(float, float, triangle, rounding)

  /** Split formats: `box` for the box lanes, `tri` for the triangle test. */
  def resolve(box: String, tri: String, triangle: String, rounding: String): Chosen[_ <: Data, _] =
    if (box == "field" || tri == "field") Chosen(FieldDatapath, FieldDatapath.Golden)
    else {
      val dp = FloatDatapath(
        FloatFormat.parse(box),
        FloatFormat.parse(tri),
        TriangleTest.parse(triangle),
        BoxRounding.parse(rounding)
      )
      Chosen(dp, FloatGolden(dp))
    }
}
