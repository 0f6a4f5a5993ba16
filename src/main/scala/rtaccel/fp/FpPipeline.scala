package rtaccel.fp

import chisel3._
import chisel3.util._

/** Spreads a unit's `latency` registers evenly over its `cuts` cut points (in
  * dataflow order; the last one is the output). Cut point i gets
  * floor((i+1)L/K) - floor(iL/K) registers, so with L < K the registers sit at
  * evenly spaced cuts, and with L > K some cuts get several (to be spread by
  * the synthesis tool's retiming). Data registers load only on valid beats.
  */
class FpPipeline(val latency: Int, val cuts: Int) {
  require(latency >= 0, s"FpPipeline: latency must be >= 0, got $latency")
  require(cuts >= 1, s"FpPipeline: needs at least one cut point, got $cuts")
  private var next = 0

  def registersAt(i: Int): Int = (i + 1) * latency / cuts - i * latency / cuts

  /** Passes (valid, data) through the next cut point. */
  def cut[T <: Data](valid: Bool, data: T): Valid[T] = {
    require(next < cuts, s"FpPipeline: more than $cuts cut points used")
    val n = registersAt(next)
    next += 1
    Pipe(valid, data, n)
  }

  /** Checks at elaboration that the unit used every cut, so its latency is exactly `latency`. */
  def done(): Unit = require(next == cuts, s"FpPipeline: only $next of $cuts cut points used")
}

/** Threads a unit's valid bit through its cut points in dataflow order:
  * `stages(x)` is `x` after the next cut point of `pipe`.
  */
final class FpStages(pipe: FpPipeline, valid0: Bool) {
  private var v = valid0
  def valid: Bool = v
  def apply[T <: Data](data: T): T = {
    val o = pipe.cut(v, data)
    v = o.valid
    o.bits
  }
}
