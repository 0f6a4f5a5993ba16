package rtaccel.regress

import chisel3.Data
import rtaccel.Datapath
import rtaccel.golden.ArithGolden
import rtaccel.system.FieldDatapath

/** A datapath and its golden model, which must agree bit for bit. */
final case class Chosen[T <: Data, S](dp: Datapath[T], golden: ArithGolden[S])

object DatapathChoice {
  /** Resolves `make regress` FLOAT / TRIANGLE / ROUNDING to a datapath. */
  def resolve(float: String, triangle: String, rounding: String): Chosen[_ <: Data, _] =
    (float, triangle, rounding) match {
      case ("field", _, _) => Chosen(FieldDatapath, FieldDatapath.Golden)
      case _ =>
        throw new IllegalArgumentException(
          s"no datapath for FLOAT=$float TRIANGLE=$triangle ROUNDING=$rounding yet: the floating-point datapaths are issue 4")
    }
}
