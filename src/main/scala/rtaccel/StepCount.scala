package rtaccel

import chisel3._

/** A count that moves by at most one a cycle, `countReg`, with registered flags beside it: `is(k)` is
  * `countReg === k` for each k in `flagValues`, kept as the count moves rather than compared after it.
  *
  * Why: where a count was summed from its events and compared afterwards, the late event (a ready, a valid, a
  * table read) ran through the carry chain into the flag's compare (docs/fmax.md). Here the next count and each
  * next flag are one select, by the two events, among values formed from registers alone: the count, its +1
  * and its -1, and for the flags the compares `countReg === k - 1` and `countReg === k + 1`, each read from the
  * neighbouring flag's register when that value is flagged too (so a run of flags 0..m shifts, with one compare
  * at its end). The caller keeps the count within 0 until 2^width (a step past either end is its bug): so a step
  * up never lands on 0, nor a step down on 2^width - 1.
  *
  * Its registers live in the calling module, as [[HeldCount]]'s do, so a unit's Fmax estimate sees them as its
  * own; they are named `<name>Reg` and `<name>Is<k>Reg` there.
  */
final class StepCount(name: String, width: Int, flagValues: Seq[Int] = Nil, init: Int = 0) {
  require(width >= 1, s"StepCount: width $width")
  require(flagValues.distinct.size == flagValues.size, s"StepCount: flag values repeat: $flagValues")
  require(init >= 0 && init < (BigInt(1) << width), s"StepCount: init $init does not fit $width bits")
  private val modulus = BigInt(1) << width
  flagValues.foreach(k => require(k >= 0, s"StepCount: flag value $k below 0"))

  val countReg: UInt = RegInit(init.U(width.W)).suggestName(s"${name}Reg")
  // A flag for a value the width cannot hold is a constant false (a unit sized down for formal keeps its
  // flag vector's shape).
  private val flagRegs: Seq[(Int, Bool)] = flagValues.map { k =>
    k -> (if (k < modulus) RegInit((k == init).B).suggestName(s"${name}Is${k}Reg") else false.B)
  }

  /** `countReg === k`, from its register. */
  def is(k: Int): Bool = flagRegs
    .collectFirst { case (`k`, r) => r }
    .getOrElse(throw new IllegalArgumentException(s"StepCount: no flag for $k (has ${flagValues.mkString(", ")})"))

  // countReg === v: the flag's register when v is flagged, else a compare of the register with a constant; false
  // for a v outside the count's range (the step from it would wrap).
  private def valueIs(v: BigInt): Bool =
    if (v < 0 || v >= modulus) false.B
    else flagRegs.collectFirst { case (k, r) if BigInt(k) == v => r }.getOrElse(countReg === v.U(width.W))

  /** This cycle's events: `up` adds one, `down` takes one, both or neither leave the count. Call once. */
  def step(up: Bool, down: Bool): Unit = {
    val plus = up && !down
    val minus = down && !up
    countReg := Mux(plus, countReg + 1.U, Mux(minus, countReg - 1.U, countReg))
    for ((k, r) <- flagRegs if k < modulus)
      r := Mux(plus, valueIs(BigInt(k) - 1), Mux(minus, valueIs(BigInt(k) + 1), r))
  }

  /** Every flag equals its compare (for an assertion in the caller). */
  def flagsAgree: Bool =
    flagRegs.collect { case (k, r) if k < modulus => r === (countReg === k.U) }.foldLeft(true.B)(_ && _)
}
