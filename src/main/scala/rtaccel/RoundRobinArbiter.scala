package rtaccel

import chisel3._
import chisel3.util._

/** chisel3.util's RRArbiter, cycle for cycle (the same grants, `chosen` and pointer), built for a short path.
  *
  * RRArbiter forms `chosen` as a binary index through a chain of priority selects and then selects `bits` by
  * that index: a pointer register, the priority chain and an n-to-1 multiplexer in a row, 8-10 LUT and MUXF cells
  * for eight inputs (docs/fmax.md). Here the grant is one-hot, from the inputs' valids and a mask register (the
  * inputs above the last grant), and `bits` is an AND-OR over the grant, so each output is a few LUT levels from
  * the valids; `chosen` is encoded from the one-hot grant beside the data select.
  */
class RoundRobinArbiter[T <: Data](gen: T, n: Int) extends Module {
  require(n >= 1, s"RoundRobinArbiter: $n inputs")
  val io = IO(new ArbiterIO(gen, n))

  // Input i is above the last grant (RRArbiter's grantMask, from its lastGrant register, reset to 0).
  private val aboveReg = RegInit(((BigInt(1) << n) - 2).U(n.W))
  private val valids = VecInit(io.in.map(_.valid)).asUInt
  private val above = valids & aboveReg
  // The lowest valid input above the last grant; if none, the lowest valid input.
  private val grant = Mux(above.orR, PriorityEncoderOH(above), PriorityEncoderOH(valids))
  io.out.valid := valids.orR
  io.out.bits := Mux1H(grant, io.in.map(_.bits))
  io.chosen := OHToUInt(grant)
  for ((in, i) <- io.in.zipWithIndex) in.ready := io.out.ready && grant(i)
  // The new mask: the inputs above the granted one, which is the lowest input of `above` if any, else the lowest
  // valid input; so it is formed from the requests beside the grant, not behind it (an OR of the grant bits below
  // each input, behind the grant, was ReadEngine's longest path with 8 clients, 5.00 ns, docs/fmax.md).
  private def aboveLowest(x: UInt): UInt =
    VecInit((0 until n).map(i => if (i == 0) false.B else x(i - 1, 0).orR)).asUInt
  when(io.out.fire) { aboveReg := Mux(above.orR, aboveLowest(above), aboveLowest(valids)) }
}
