package rtaccel.fp

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.testutil.Seeded

import scala.util.Random

/** The golden model checked against independent references: JVM `Float`
  * (FP32 RNE) and `Double` (e11m52 RNE) arithmetic, and, for every format and
  * mode, the IEEE definition of rounding evaluated with exact rationals.
  * Pure Scala, no simulator, so it runs millions of cases.
  */
class FpModelSpec extends AnyFlatSpec {
  import FpModel._
  import RoundingMode._
  private val F32 = FloatFormat.FP32
  private val F64 = FloatFormat.FP64
  private def hex(x: BigInt) = "0x" + x.toString(16)

  /** FP32 model results for (a, b) vs JVM Float, every NaN counted equal (`f32Bits`). */
  private def checkF32(a: BigInt, b: BigInt, where: String): Unit = {
    val (fa, fb) = (f32(a), f32(b))
    def chk(op: String, got: BigInt, want: Float): Unit =
      assert(
        got == f32Bits(want),
        s"$where: $op(${hex(a)}, ${hex(b)}) = ${hex(got)}, JVM ${hex(f32Bits(want))} ($fa, $fb)"
      )
    chk("add", add(F32, RNE, a, b), fa + fb)
    chk("sub", sub(F32, RNE, a, b), fa - fb)
    chk("mul", mul(F32, RNE, a, b), fa * fb)
    chk("div", div(F32, RNE, a, b), fa / fb)
    chk("recip", recip(F32, RNE, a), 1f / fa)
    assert(
      lt(F32, a, b) == (fa < fb) && equal(F32, a, b) == (fa == fb) && le(F32, a, b) == (fa <= fb),
      s"$where: compare(${hex(a)}, ${hex(b)})"
    )
    // minimumNumber/maximumNumber: Math.min/max except that a NaN operand loses.
    def numMin(x: Float, y: Float) = if (x.isNaN) y else if (y.isNaN) x else Math.min(x, y)
    def numMax(x: Float, y: Float) = if (x.isNaN) y else if (y.isNaN) x else Math.max(x, y)
    chk("min", min(F32, a, b), numMin(fa, fb))
    chk("max", max(F32, a, b), numMax(fa, fb))
    // Non-NaN min/max return an operand bit for bit (raw bits, not canonicalised).
    if (!fa.isNaN && !fb.isNaN) assert(min(F32, a, b) == f32RawBits(Math.min(fa, fb)), s"$where: min keeps bits")
  }

  "FpModel (FP32, RNE)" should "match JVM Float on every pair of corner values" in {
    for ((a, b) <- FpOperands.cornerPairs(F32)) checkF32(a, b, "corner")
  }

  it should "match JVM Float on 1,000,000 random pairs (mixed exponents)" in Seeded("FpModel.f32.random") { rnd =>
    val t0 = System.nanoTime()
    for (i <- 0 until 1000000) { val (a, b) = FpOperands.pair(F32, rnd); checkF32(a, b, s"case $i") }
    val secs = (System.nanoTime() - t0) / 1e9
    info(f"1M pairs x 10 operations in $secs%.1f s, with operand generation and JVM reference")
    // Speed of the model alone (a report, not a pass/fail criterion).
    val pairs = Array.fill(200000)(FpOperands.pair(F32, rnd))
    for (
      (name, op) <- Seq[(String, (BigInt, BigInt) => BigInt)](
        ("add", add(F32, RNE, _, _)),
        ("mul", mul(F32, RNE, _, _)),
        ("div", div(F32, RNE, _, _))
      )
    ) {
      val t = System.nanoTime()
      var sink = 0
      for ((a, b) <- pairs) sink ^= op(a, b).hashCode
      info(f"model $name: ${pairs.length / ((System.nanoTime() - t) / 1e9) / 1e6}%.2f M ops/s ($sink%x)")
    }
  }

  it should "convert to and from wider/narrower formats as JVM Float/Double casts do" in Seeded("FpModel.f32.convert") {
    rnd =>
      for (i <- 0 until 200000) {
        val a = if (i < 64) FpOperands.corners(F32)(i % FpOperands.corners(F32).size) else FpOperands.single(F32, rnd)
        val wide = fromFloat32(F64, RNE, a)
        assert(
          wide == (BigInt(java.lang.Double.doubleToLongBits(f32(a).toDouble)) & ((BigInt(1) << 64) - 1)),
          s"widen ${hex(a)}"
        )
        assert(toFloat32(F64, RNE, wide) == f32Bits(f32(a)), s"round trip ${hex(a)}")
        assert(fromFloat32(F32, RDN, a) == (if (F32.isNaN(a)) F32.canonicalNaN else a), s"identity ${hex(a)}")
        val d = FpOperands.single(F64, rnd)
        val want = f32Bits(java.lang.Double.longBitsToDouble(d.toLong).toFloat)
        assert(toFloat32(F64, RNE, d) == want, s"narrow ${hex(d)}")
      }
  }

  "FpModel (e11m52, RNE)" should "match JVM Double on corners and 200,000 random pairs" in Seeded(
    "FpModel.f64.random"
  ) { rnd =>
    def dbl(x: BigInt) = java.lang.Double.longBitsToDouble(x.toLong)
    def bits(d: Double) = BigInt(java.lang.Double.doubleToLongBits(d)) & ((BigInt(1) << 64) - 1)
    val pairs = FpOperands.cornerPairs(F64) ++ Seq.fill(200000)(FpOperands.pair(F64, rnd))
    for ((a, b) <- pairs) {
      val (x, y) = (dbl(a), dbl(b))
      assert(add(F64, RNE, a, b) == bits(x + y), s"add(${hex(a)}, ${hex(b)})")
      assert(mul(F64, RNE, a, b) == bits(x * y), s"mul(${hex(a)}, ${hex(b)})")
      assert(div(F64, RNE, a, b) == bits(x / y), s"div(${hex(a)}, ${hex(b)})")
    }
  }

  /** The formats the project uses, plus odd ones that stress the generic code. */
  private val formats = Seq(
    F32,
    FloatFormat(8, 15),
    FloatFormat(8, 12),
    FloatFormat(8, 10),
    FloatFormat(8, 7),
    FloatFormat(6, 9),
    FloatFormat(5, 10),
    FloatFormat(3, 2),
    F64
  )

  for (fmt <- formats) {
    s"FpModel ($fmt, all modes)" should "round add/sub/mul/div/convert as IEEE defines (RDN <= exact <= RUP, adjacent; RTZ; RNE nearest-even)" in
      Seeded(s"FpModel.$fmt.directed") { rnd =>
        def check(what: String, exact: Rational, r: RoundingMode => BigInt, in: FloatFormat = fmt): Unit =
          FpExact.checkRoundings(in, exact, r).foreach(msg => fail(s"$fmt $what: $msg"))
        val pairs = FpOperands.cornerPairs(fmt) ++ Seq.fill(20000)(FpOperands.pair(fmt, rnd))
        var checked = 0
        for ((a, b) <- pairs if fmt.isFinite(a) && fmt.isFinite(b)) {
          val (va, vb) = (FpExact.value(fmt, a), FpExact.value(fmt, b))
          val tag = s"(${hex(a)}, ${hex(b)})"
          check(s"add$tag", va + vb, add(fmt, _, a, b))
          check(s"sub$tag", va - vb, sub(fmt, _, a, b))
          check(s"mul$tag", va * vb, mul(fmt, _, a, b))
          if (vb.num != 0) check(s"div$tag", va / vb, div(fmt, _, a, b))
          if (va.num != 0) check(s"recip$tag", Rational(1, 1) / va, recip(fmt, _, a))
          checked += 1
        }
        // Conversions from FP32 (narrowing for most formats) and back.
        for (_ <- 0 until 20000) {
          val x = FpOperands.single(F32, rnd)
          if (F32.isFinite(x)) check(s"fromFloat32(${hex(x)})", FpExact.value(F32, x), fromFloat32(fmt, _, x))
          val y = FpOperands.single(fmt, rnd)
          if (fmt.isFinite(y)) check(s"toFloat32(${hex(y)})", FpExact.value(fmt, y), toFloat32(fmt, _, y), in = F32)
        }
        assert(checked > 10000, s"only $checked finite pairs were generated")
        // Sign of exact zero sums (IEEE 754 6.3): +0 except in RDN.
        val x = fmt.one(false)
        assert(add(fmt, RNE, x, fmt.negate(x)) == fmt.zero(false) && add(fmt, RDN, x, fmt.negate(x)) == fmt.zero(true))
      }
  }

  "FpModel sub in RDN and RUP" should "give a result of the operands' exact order, on every pair of two small formats (BoxKernel picks its reciprocal by the compare)" in {
    // BoxKernel chooses R+ or R- by lt(bmin, o) and gt(bmax, o) instead of the
    // rounded difference's sign; this is the equivalence it relies on, every
    // special value and subnormal included (gradual underflow: a nonzero
    // difference never rounds to zero).
    for (fmt <- Seq(FloatFormat(3, 2), FloatFormat(4, 3))) {
      val all = (0 until (1 << fmt.width)).map(BigInt(_))
      def below(r: BigInt) = fmt.sign(r) && !fmt.isZero(r) && !fmt.isNaN(r)
      def above(r: BigInt) = !fmt.sign(r) && !fmt.isZero(r) && !fmt.isNaN(r)
      for (a <- all; b <- all) {
        val (dn, up) = (sub(fmt, RDN, a, b), sub(fmt, RUP, a, b))
        assert(below(dn) == lt(fmt, a, b), s"$fmt: RDN(${hex(a)} - ${hex(b)}) = ${hex(dn)}, lt = ${lt(fmt, a, b)}")
        assert(above(up) == lt(fmt, b, a), s"$fmt: RUP(${hex(a)} - ${hex(b)}) = ${hex(up)}, gt = ${lt(fmt, b, a)}")
      }
    }
  }

  "FpModel min/max" should "let a NaN lose, order -0 below +0, and return NaN only for two NaNs" in {
    for (fmt <- formats) {
      val (pz, nz, one, nan) = (fmt.zero(false), fmt.zero(true), fmt.one(false), fmt.canonicalNaN)
      assert(min(fmt, pz, nz) == nz && min(fmt, nz, pz) == nz && max(fmt, pz, nz) == pz && max(fmt, nz, pz) == pz)
      assert(min(fmt, nan, one) == one && max(fmt, one, nan) == one && min(fmt, nan, nan) == nan)
      assert(!lt(fmt, nz, pz) && equal(fmt, nz, pz) && !equal(fmt, nan, nan) && !le(fmt, nan, one))
    }
  }

  "FloatFormat" should "classify every corner and reject out-of-range bit patterns" in {
    for (fmt <- formats) {
      assert(fmt.classify(fmt.minSubnormal(true)) == FpClass.Subnormal)
      assert(fmt.classify(fmt.minNormal(false)) == FpClass.Normal && fmt.classify(fmt.zero(true)) == FpClass.Zero)
      assert(fmt.classify(fmt.infinity(true)) == FpClass.Infinity && fmt.classify(fmt.canonicalNaN) == FpClass.NaN)
      val e = intercept[IllegalArgumentException](fmt.checkBits(BigInt(1) << fmt.width))
      assert(e.getMessage.contains(fmt.name))
    }
    assert(FloatFormat.FP32.canonicalNaN == f32Bits(Float.NaN))
  }
}
