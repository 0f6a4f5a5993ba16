package rtaccel.fetch

import chisel3._
import rtaccel.{AccelConfig, ErrorFlags}

/** A ray as the host gives it: FP32 origin, direction, tmin and tmax. */
class RawRay extends Bundle {
  val origin = Vec(3, UInt(32.W))
  val dir = Vec(3, UInt(32.W))
  val tmin = UInt(32.W)
  val tmax = UInt(32.W)
}

/** What the host sends: its own ray number, the ray, and whether it is a shadow (any-hit) ray. */
class RayIn extends Bundle {
  val number = UInt(32.W)
  val ray = new RawRay
  val shadow = Bool()
}

/** A ray's per-ray constants, computed once when it enters. */
class PreparedRay[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val statics = gen.cloneType

  /** tmax in the triangle format (the leaf unit updates it; box lanes narrow it). */
  val tmax = UInt(cfg.triFloat.width.W)

  /** Direction sign per axis (true = negative), for near-child order. */
  val dirNeg = Vec(3, Bool())

  /** InvalidRay when a component is NaN or infinite. */
  val errors = ErrorFlags()
}

/** Computes a ray's constants (format conversion, reciprocal direction,
  * shear, validity): one ray per cycle in, the result `latency` cycles later.
  */
abstract class RayPrepUnit[T <: Data](val cfg: AccelConfig, val gen: T) extends Module {
  def latency: Int
  val io = IO(new Bundle {
    val in = Flipped(chisel3.util.Valid(new RawRay))
    val out = chisel3.util.Valid(new PreparedRay(cfg, gen))
  })
}
