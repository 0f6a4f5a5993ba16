package rtaccel

import chisel3._
import chisel3.util._

/** An event counter `width` bits wide that adds `inc` each cycle and reads exactly, with no carry chain
  * behind the increment's own logic and none longer than half its width: a 64-bit counter's one
  * 64-bit chain, fed by the event, was the longest path of the units that kept one (docs/fmax.md). Its
  * registers live in the calling module, so the per-unit Fmax estimate sees them as the unit's own.
  *
  * The count is three parts, `Cat(highReg, midReg, lowReg)`. `lowReg` has the increment's width b and
  * adds it; its carry out `c` is the one event the wider parts count. `midReg` (half the width) adds
  * `c` as an enable; whether it is all ones is kept registered (`midOnesReg`, from a compare of the
  * register, not of its next value), so `highReg` adds `c && midOnesReg`, again as an enable. The only
  * chains are a b-bit add behind `inc` and the +1 of `midReg` and `highReg`, each from its register.
  */
object PerfCounter {

  /** The count so far of `inc` per cycle (a Bool's asUInt counts events), `width` bits, from 0 at reset. */
  def apply(inc: UInt, width: Int = 64): UInt = {
    val b = inc.getWidth
    val midBits = width / 2
    val highBits = width - b - midBits
    require(b >= 1 && highBits >= 1, s"PerfCounter: a $width-bit count of a $b-bit increment leaves no high part")
    val lowReg = RegInit(0.U(b.W))
    val midReg = RegInit(0.U(midBits.W))
    val highReg = RegInit(0.U(highBits.W))
    val midOnesReg = RegInit(false.B) // midReg is all ones: false at reset, as midReg is 0
    val lowSum = lowReg +& inc
    val c = lowSum(b)
    lowReg := lowSum(b - 1, 0)
    val ones = ((BigInt(1) << midBits) - 1).U(midBits.W)
    when(c) {
      midReg := midReg + 1.U // wraps into highReg below
      midOnesReg := midReg === ones - 1.U
    }.otherwise {
      midOnesReg := midReg === ones
    }
    when(c && midOnesReg) { highReg := highReg + 1.U }
    Cat(highReg, midReg, lowReg)
  }
}
