package rtaccel.datapath

import rtaccel.fp.{FloatFormat, FpModel, RoundingMode}

/** The arithmetic a kernel is written against. Every kernel (ray setup, box,
  * Moller-Trumbore, watertight) is written once, generic over this interface,
  * and run under two interpretations: [[GoldenArith]] (bit patterns through
  * FpModel) and [[HwArith]] (FP units, pipelined). So the golden model and the
  * hardware perform the same operations in the same order by construction.
  *
  * `F` is a value of `fmt` (or, for `fromF32`, an FP32 value); `B` a bit.
  * Rounding ops take their mode per call: conservative box distances need
  * RDN/RUP next to RNE ones.
  */
trait KernelArith[F, B] {
  def fmt: FloatFormat
  def add(a: F, b: F, rm: RoundingMode): F
  def sub(a: F, b: F, rm: RoundingMode): F
  def mul(a: F, b: F, rm: RoundingMode): F
  def recip(a: F, rm: RoundingMode): F

  /** FP32 bits to `fmt`, rounded in `rm` (the identity when `fmt` is FP32). */
  def fromF32(a: F, rm: RoundingMode): F

  /** A value of `from` to `fmt`, rounded in `rm` (the identity when they are equal). */
  def convert(a: F, from: FloatFormat, rm: RoundingMode): F

  /** maximumNumber/minimumNumber (a NaN operand loses). */
  def min(a: F, b: F): F
  def max(a: F, b: F): F
  def lt(a: F, b: F): B
  def le(a: F, b: F): B
  def eq(a: F, b: F): B
  // Bit-level tests and sign changes: exact, no rounding.
  def isNaN(a: F): B
  def isZero(a: F): B
  def isNonFinite(a: F): B
  def signBit(a: F): B
  def neg(a: F): F
  def abs(a: F): F
  def mux(c: B, t: F, f: F): F
  def and(a: B, b: B): B
  def or(a: B, b: B): B
  def not(a: B): B
  def muxB(c: B, t: B, f: B): B
  def const(bits: BigInt): F
  def bool(b: Boolean): B

  // ---- derived helpers (no new operations) ----

  /** `(add(a, b, RDN), add(a, b, RUP))`: one value rounded both ways (hardware may share the exact sum). */
  def addDnUp(a: F, b: F): (F, F) = (add(a, b, RoundingMode.RDN), add(a, b, RoundingMode.RUP))

  /** `(mul(a, b, RDN), mul(a, b, RUP))`: one value rounded both ways (hardware may share the exact product). */
  def mulDnUp(a: F, b: F): (F, F) = (mul(a, b, RoundingMode.RDN), mul(a, b, RoundingMode.RUP))

  /** `(recip(a, lo), recip(a, hi))`: one reciprocal rounded in two modes (hardware may share the quotient). */
  def recipPair(a: F, lo: RoundingMode, hi: RoundingMode): (F, F) = (recip(a, lo), recip(a, hi))

  /** `modes.map(recip(a, _))`: one reciprocal rounded in several modes (hardware may share the quotient). */
  def recipModes(a: F, modes: Seq[RoundingMode]): Seq[F] = modes.map(recip(a, _))

  /** `a` itself; in hardware a register between the steps before and after it (HwArith), where wires (selects,
    * sign flips) would otherwise stack on a unit's first stage.
    */
  def cut(a: F): F = a

  def gt(a: F, b: F): B = lt(b, a)
  def ge(a: F, b: F): B = le(b, a)
  def all(bs: Seq[B]): B = bs.reduce(and)
  def any(bs: Seq[B]): B = bs.reduce(or)

  /** Picks `vs(i)` for the one-hot `sel(i)`; `sel` has one more entry than needed. */
  def select(sel: Seq[B], vs: Seq[F]): F = vs.indices.init.foldRight(vs.last)((i, rest) => mux(sel(i), vs(i), rest))

  /** IEEE `a < 0` and `a > 0` from the bits alone (false for NaN and for either zero). */
  def ltZero(a: F): B = and(signBit(a), not(or(isZero(a), isNaN(a))))
  def gtZero(a: F): B = and(not(signBit(a)), not(or(isZero(a), isNaN(a))))
  def posInf: F = const(fmt.infinity(false))
  def negInf: F = const(fmt.infinity(true))
  def posZero: F = const(fmt.zero(false))
}

/** The golden interpretation: FP bit patterns as BigInt through [[FpModel]]. */
final class GoldenArith(val fmt: FloatFormat) extends KernelArith[BigInt, Boolean] {
  def add(a: BigInt, b: BigInt, rm: RoundingMode): BigInt = FpModel.add(fmt, rm, a, b)
  def sub(a: BigInt, b: BigInt, rm: RoundingMode): BigInt = FpModel.sub(fmt, rm, a, b)
  def mul(a: BigInt, b: BigInt, rm: RoundingMode): BigInt = FpModel.mul(fmt, rm, a, b)
  def recip(a: BigInt, rm: RoundingMode): BigInt = FpModel.recip(fmt, rm, a)
  def fromF32(a: BigInt, rm: RoundingMode): BigInt =
    if (fmt == FloatFormat.FP32) a else FpModel.fromFloat32(fmt, rm, a)
  def convert(a: BigInt, from: FloatFormat, rm: RoundingMode): BigInt =
    if (fmt == from) a else FpModel.convert(from, fmt, rm, a)
  def min(a: BigInt, b: BigInt): BigInt = FpModel.min(fmt, a, b)
  def max(a: BigInt, b: BigInt): BigInt = FpModel.max(fmt, a, b)
  def lt(a: BigInt, b: BigInt): Boolean = FpModel.lt(fmt, a, b)
  def le(a: BigInt, b: BigInt): Boolean = FpModel.le(fmt, a, b)
  def eq(a: BigInt, b: BigInt): Boolean = FpModel.equal(fmt, a, b)
  def isNaN(a: BigInt): Boolean = fmt.isNaN(a)
  def isZero(a: BigInt): Boolean = fmt.isZero(a)
  def isNonFinite(a: BigInt): Boolean = !fmt.isFinite(a)
  def signBit(a: BigInt): Boolean = fmt.sign(a)
  def neg(a: BigInt): BigInt = fmt.negate(a)
  def abs(a: BigInt): BigInt = fmt.abs(a)
  def mux(c: Boolean, t: BigInt, f: BigInt): BigInt = if (c) t else f
  def and(a: Boolean, b: Boolean): Boolean = a && b
  def or(a: Boolean, b: Boolean): Boolean = a || b
  def not(a: Boolean): Boolean = !a
  def muxB(c: Boolean, t: Boolean, f: Boolean): Boolean = if (c) t else f
  def const(bits: BigInt): BigInt = fmt.checkBits(bits)
  def bool(b: Boolean): Boolean = b
}
