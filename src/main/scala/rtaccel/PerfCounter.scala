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
  * `c` as an enable; whether it is all ones is kept registered (`midOnesReg`, taken on `c` from
  * `midNearReg`, "one short of all ones", itself taken from a compare of the register), so `highReg` adds
  * `c && midOnesReg`, again as an enable. The only
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
    // midReg is one short of all ones: false at reset for a mid part of 2 bits or more, true for 1.
    val midNearReg = RegInit((midBits == 1).B)
    val lowSum = lowReg +& inc
    val c = lowSum(b)
    lowReg := lowSum(b - 1, 0)
    val ones = ((BigInt(1) << midBits) - 1).U(midBits.W)
    // Both flags follow midReg's +1 by a select on `c` between registers and a compare of the register: compared
    // after `c`, the compares' LUTs came after the low add's chain (7.49 ns in the core's control, docs/fmax.md).
    when(c) {
      midReg := midReg + 1.U // wraps into highReg below
      midOnesReg := midNearReg
      midNearReg := (if (midBits == 1) midOnesReg else midReg === ones - 2.U)
    }
    when(c && midOnesReg) { highReg := highReg + 1.U }
    Cat(highReg, midReg, lowReg)
  }
}
