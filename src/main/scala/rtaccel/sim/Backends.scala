package rtaccel.sim

import chiseltest._
import firrtl2.AnnotationSeq

/** Simulator choices. Treadle starts instantly and suits short cycle-by-cycle
  * specs; Verilator pays a build (20-35 s for an FP-heavy unit) but runs about
  * 5x faster, so anything over a few thousand cycles uses it. The caching
  * annotation reuses a build when the design is unchanged.
  */
object Backends {
  val treadle: AnnotationSeq = Seq(TreadleBackendAnnotation)
  val verilator: AnnotationSeq = Seq(VerilatorBackendAnnotation, chiseltest.internal.CachingAnnotation)
}
