package rtaccel.datapath

import chisel3._
import chisel3.util.RegEnable
import rtaccel.fp._

import scala.collection.mutable

/** The valid bit of an II = 1 pipeline at each of its cycles: `at(c)` is the
  * input's valid delayed by `c` (reset to false), one shared register chain.
  *
  * It also enables the pipeline's delay registers ([[Timed]]). A register
  * whose output some logic reads loads when its own slot is valid, `at(c)`,
  * and so does one in a short run of registers that only pass a value on; a
  * run of at least [[ValidChain.ShiftRun]] loads on `load(c)`: the input's
  * valid at c = 0, past it one enable shared by the whole pipeline, `busyReg`
  * (some slot after the input is valid). Either way a valid operation's value
  * moves a stage every cycle it is in the pipeline and arrives unchanged (the
  * same bits as with free-running registers), and an idle unit holds its
  * registers still (the C++ model skips its logic, docs/cppsim.md). With one
  * enable, the pass-through registers of a delay chain become shift-register
  * LUTs (SRLC32E: 32 stages of a bit in one LUT) instead of a flip-flop per bit
  * and stage, and each value the logic reads still leaves a flip-flop: an SRL's
  * clock-to-out is about a nanosecond longer (docs/fmax.md).
  *
  * A module makes its chains with [[ValidChains.validChain]], which builds
  * them when the module's body is done, when every use is known.
  */
final class ValidChain private[datapath] (valid: Bool) {
  private val taps = mutable.ArrayBuffer[Bool](valid)
  private val delayed = mutable.ArrayBuffer[Timed[_ <: Data]]()
  private var finished = false
  def at(cycle: Int): Bool = {
    require(cycle >= 0, s"ValidChain: cycle $cycle < 0")
    while (taps.size <= cycle) taps += RegNext(taps.last, false.B)
    taps(cycle)
  }

  // Made on the first pass-through run that needs it; driven by finish(), once every tap exists.
  private var busy: Option[Bool] = None

  /** The enable of a pass-through delay register whose input is at cycle `cycle`. */
  def load(cycle: Int): Bool = {
    require(cycle >= 0, s"ValidChain: cycle $cycle < 0")
    if (cycle == 0) valid
    else busy.getOrElse { val w = Wire(Bool()); busy = Some(w); w }
  }

  private[datapath] def delays(t: Timed[_ <: Data]): Unit = {
    require(!finished, "ValidChain: a delay used after finish()")
    delayed += t
  }

  /** Builds every delay chain, then `busyReg`: at cycle t the OR of every tap at t - 1, so true exactly when some
    * slot from cycle 1 to the chain's end is valid at t. */
  private[datapath] def finish(): Unit = {
    require(!finished, "ValidChain: finished twice")
    finished = true
    delayed.foreach(_.build())
    busy.foreach { b =>
      val busyReg = RegNext(taps.reduce(_ || _), false.B)
      b := busyReg
    }
  }
}

/** A module whose pipelines follow [[ValidChain]]s: each is finished (its delay chains and shared enable built)
  * when the module's body is done. */
trait ValidChains extends RawModule {
  protected def validChain(valid: Bool): ValidChain = {
    val c = new ValidChain(valid)
    atModuleBodyEnd(c.finish())
    c
  }
}

object ValidChain {

  /** Pass-through runs at least this long load on the shared enable and become shift-register LUTs; shorter ones
    * stay flip-flops. A run of r registers of a bit is r flip-flops or one LUT (up to 32 stages), and LUTs are the
    * scarcer: runs of 16 and more hold most of the flip-flops for half the LUTs that every run of 3 and more (the
    * shortest Yosys maps) would take (docs/fmax.md). */
  val ShiftRun: Int = 16
}

/** A hardware value with the pipeline cycle at which it is valid. `at(c)`
  * gives it delayed to cycle `c`; delays share one register chain per value
  * (every consumer taps the same chain), so aligning an operand for several
  * later operations costs the longest delay once, not once per use. The chain
  * is built by its [[ValidChain]]'s `finish`: the registers whose outputs are
  * used load when their slot is valid, the others on the shared enable, so
  * a valid operation's value arrives unchanged; between operations the chain
  * holds. Constants are valid at every cycle and cost no registers.
  */
final class Timed[T <: Data](val value: T, val ready: Int, val valid: ValidChain, val constant: Boolean = false) {
  private val uses = mutable.LinkedHashMap.empty[Int, T]
  def at(cycle: Int): T = {
    require(constant || cycle >= ready, s"Timed: value ready at $ready used at $cycle")
    if (constant || cycle == ready) value
    else
      uses.getOrElseUpdate(
        cycle - ready, {
          if (uses.isEmpty) valid.delays(this)
          Wire(chiselTypeOf(value))
        }
      )
  }

  private[datapath] def build(): Unit = {
    var x = value
    val used = (0 +: uses.keys.toSeq.sorted)
    // Between two uses, the registers of a run shorter than ValidChain.ShiftRun stay flip-flops; the last one, read
    // by its use, loads on its own slot's valid either way.
    for (Seq(prev, next) <- used.sliding(2); k <- prev + 1 to next) {
      val c = ready + k - 1
      x = RegEnable(x, if (k == next || next - prev - 1 < ValidChain.ShiftRun) valid.at(c) else valid.load(c))
      uses.get(k).foreach(_ := x)
    }
  }
}

/** The hardware interpretation of [[KernelArith]]: each rounding operation or
  * comparison instantiates an FP unit with a fixed mode and its own latency,
  * fed by operands aligned to the later one's cycle. The result is an II = 1
  * pipeline whose latency is the `ready` of its outputs: derived from the unit
  * latencies, never typed. Bit tests, sign flips and muxes are wires.
  * Every unit and delay register is enabled by `valid`, the pipeline's
  * [[ValidChain]] (units that share one pipeline share it).
  * Must be used inside a Module (it instantiates units there).
  */
final class HwArith(val fmt: FloatFormat, val valid: ValidChain) extends KernelArith[Timed[UInt], Timed[Bool]] {
  type F = Timed[UInt]
  type B = Timed[Bool]
  private val f32 = FloatFormat.FP32
  private def when2(a: Timed[_ <: Data], b: Timed[_ <: Data]): Int = a.ready max b.ready

  private def binary(unit: FpUnitIO[FpBinaryIn, UInt], latency: Int, a: F, b: F): F = {
    val c = when2(a, b)
    unit.in.valid := valid.at(c)
    unit.in.bits.a := a.at(c)
    unit.in.bits.b := b.at(c)
    new Timed(unit.out.bits, c + latency, valid)
  }
  def add(a: F, b: F, rm: RoundingMode): F = { val u = Module(new FpAdd(fmt, Some(rm))); binary(u.io, u.latency, a, b) }
  def sub(a: F, b: F, rm: RoundingMode): F = {
    val u = Module(new FpAdd(fmt, Some(rm), subtract = true)); binary(u.io, u.latency, a, b)
  }
  def mul(a: F, b: F, rm: RoundingMode): F = { val u = Module(new FpMul(fmt, Some(rm))); binary(u.io, u.latency, a, b) }
  private def dnUp(io: FpUnitIO[FpBinaryIn, FpDnUp], latency: Int, a: F, b: F): (F, F) = {
    val c = when2(a, b)
    io.in.valid := valid.at(c)
    io.in.bits.a := a.at(c)
    io.in.bits.b := b.at(c)
    (new Timed(io.out.bits.dn, c + latency, valid), new Timed(io.out.bits.up, c + latency, valid))
  }
  override def addDnUp(a: F, b: F): (F, F) = { val u = Module(new FpAddDnUp(fmt)); dnUp(u.io, u.latency, a, b) }
  override def mulDnUp(a: F, b: F): (F, F) = { val u = Module(new FpMulDnUp(fmt)); dnUp(u.io, u.latency, a, b) }
  private def unary[T <: Data](io: FpUnitIO[FpUnaryIn, T], latency: Int, a: F): Timed[T] = {
    io.in.valid := valid.at(a.ready)
    io.in.bits.a := a.at(a.ready)
    new Timed(io.out.bits, a.ready + latency, valid)
  }
  def recip(a: F, rm: RoundingMode): F = { val u = Module(new FpRecip(fmt, Some(rm))); unary(u.io, u.latency, a) }
  override def recipPair(a: F, lo: RoundingMode, hi: RoundingMode): (F, F) = {
    val u = Module(new FpRecipPair(fmt, lo, hi))
    val r = unary(u.io, u.latency, a)
    (field(r)(_.lo), field(r)(_.hi))
  }
  override def recipModes(a: F, modes: Seq[RoundingMode]): Seq[F] = {
    val u = Module(new FpRecipModes(fmt, modes))
    val r = unary(u.io, u.latency, a)
    modes.indices.map(i => field(r)(_(i)))
  }
  def fromF32(a: F, rm: RoundingMode): F = convert(a, f32, rm)
  def convert(a: F, from: FloatFormat, rm: RoundingMode): F =
    if (fmt == from) a
    else { val u = Module(new FpConvert(from, fmt, Some(rm))); unary(u.io, u.latency, a) }

  /** One comparator per operand pair, shared by every min/max/lt/le/eq on it:
    * FpCompare's logic and its output register (the unit's latency), built
    * in place rather than as an FpCompare module, so that synthesis drops the
    * outputs no use reads (most uses read one flag; a min or max against a
    * constant infinity folds). Bit for bit the unit's result, as its spec
    * checks the same `FpCompare.logic`.
    */
  private val compares = mutable.Map.empty[(F, F), Timed[FpCompareOut]]
  private def compare(a: F, b: F): Timed[FpCompareOut] = compares.getOrElseUpdate(
    (a, b), {
      val c = when2(a, b)
      val latency = FpCompare.defaultLatency
      val out = (0 until latency).foldLeft(FpCompare.logic(fmt, a.at(c), b.at(c))) { (x, i) =>
        RegEnable(x, valid.at(c + i))
      }
      new Timed(out, c + latency, valid)
    }
  )
  private def field[S <: Data, T <: Data](t: Timed[S])(f: S => T): Timed[T] = new Timed(f(t.value), t.ready, valid)
  // min(+inf, x) and max(-inf, x) are x unless x is NaN (a NaN loses, as in FpModel.min/max): that value, after
  // the comparator's latency, without its compare (BoxKernel's folds start from these constants, and the
  // compare of a selected operand with a constant was a box lane's longest path, docs/fmax.md).
  private def againstInf(a: F, b: F, inf: BigInt): Option[F] = {
    def isInf(t: F): Boolean = t.constant && t.value.litOption.contains(inf)
    val other = if (isInf(a)) Some(b) else if (isInf(b)) Some(a) else None
    other.filter(!_.constant).map { x =>
      val v = wire1(x, y => Mux(nanBits(y), inf.U(fmt.width.W), y))
      val c = x.ready + FpCompare.defaultLatency
      new Timed(v.at(c), c, valid)
    }
  }
  def min(a: F, b: F): F = againstInf(a, b, fmt.infinity(false)).getOrElse(field(compare(a, b))(_.min))
  def max(a: F, b: F): F = againstInf(a, b, fmt.infinity(true)).getOrElse(field(compare(a, b))(_.max))
  def lt(a: F, b: F): B = field(compare(a, b))(_.lt)
  def le(a: F, b: F): B = field(compare(a, b))(o => o.lt || o.eq)
  def eq(a: F, b: F): B = field(compare(a, b))(_.eq)

  private def wire1[T <: Data](a: F, f: UInt => T): Timed[T] = new Timed(f(a.value), a.ready, valid, a.constant)
  private def exp(x: UInt): UInt = x(fmt.width - 2, fmt.manBits)
  private def man(x: UInt): UInt = x(fmt.manBits - 1, 0)
  private def nanBits(x: UInt): Bool = exp(x).andR && man(x).orR
  def isNaN(a: F): B = wire1(a, nanBits)
  def isZero(a: F): B = wire1(a, x => x(fmt.width - 2, 0) === 0.U)
  def isNonFinite(a: F): B = wire1(a, x => exp(x).andR)
  def signBit(a: F): B = wire1(a, x => x(fmt.width - 1))
  def neg(a: F): F = wire1(a, x => (x ^ (BigInt(1) << (fmt.width - 1)).U(fmt.width.W)))
  def abs(a: F): F = wire1(a, x => x(fmt.width - 2, 0).pad(fmt.width))

  private def comb2[S <: Data, T <: Data](a: Timed[S], b: Timed[S], f: (S, S) => T): Timed[T] = {
    val c = when2(a, b)
    new Timed(f(a.at(c), b.at(c)), c, valid, a.constant && b.constant)
  }
  private def comb3[S <: Data](c: B, t: Timed[S], e: Timed[S]): Timed[S] = {
    val r = c.ready max t.ready max e.ready
    new Timed(Mux(c.at(r), t.at(r), e.at(r)), r, valid, c.constant && t.constant && e.constant)
  }
  def mux(c: B, t: F, f: F): F = comb3(c, t, f)
  def muxB(c: B, t: B, f: B): B = comb3(c, t, f)
  def and(a: B, b: B): B = comb2[Bool, Bool](a, b, _ && _)
  def or(a: B, b: B): B = comb2[Bool, Bool](a, b, _ || _)
  def not(a: B): B = new Timed(!a.value, a.ready, valid, a.constant)
  def const(bits: BigInt): F = new Timed(fmt.checkBits(bits).U(fmt.width.W), 0, valid, constant = true)
  def bool(b: Boolean): B = new Timed(b.B, 0, valid, constant = true)

  override def cut(a: F): F = if (a.constant) a else new Timed(a.at(a.ready + 1), a.ready + 1, valid)

  /** An input valid at cycle 0. */
  def input(x: UInt): F = new Timed(x, 0, valid)
  def inputB(x: Bool): B = new Timed(x, 0, valid)
}
