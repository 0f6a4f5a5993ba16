package rtaccel.fp

/** One Newton-Raphson step of [[FpRecipPlan]]: `y' = y + y (1 - b y)` with
  * `y` in `fIn` fraction bits and `y'` in `fOut`. The error term `1 - b y` is
  * exact as an integer `E`; it is shifted right by `drop` bits (floor) and
  * kept in `eWidth` signed bits before it multiplies `y`, and the product is
  * floored to `fOut` bits.
  */
case class FpRecipStep(fIn: Int, fOut: Int, drop: Int, eWidth: Int) {

  /** The product `y E'` is shifted right by this much onto `fOut` fraction bits. */
  def productShift(p: Int): Int = p - 1 + 2 * fIn - drop - fOut
}

/** How [[FpRecipCore]] computes the reciprocal's quotient for precision `p`:
  * `Q = floor(2^(2p) / B)` and whether the division is exact, for a
  * normalised significand `B` in `[2^(p-1), 2^p)`, i.e. `b = B 2^(1-p)` in
  * [1, 2). These are the quotient bits and sticky bit the digit recurrence
  * ([[FpDivCore]]) gives, so the rounder makes the same result in every mode.
  *
  *  1. A table indexed by the `k` bits of `b` below its leading one gives
  *     `y0`, the reciprocal of the interval's midpoint rounded to `m`
  *     fraction bits: `|1/b - y0| <= 2^-(k+1) + 2^-(m+1)` (the interval is
  *     `2^-k` wide and `b >= 1`). For `p - 1 <= maxIndexBits` the index is all
  *     of `b` and `y0` is `1/b` rounded to `p + 1` bits.
  *  2. Newton-Raphson steps ([[FpRecipStep]]) in integers on the DSP48s:
  *     `1/b - y' = b (1/b - y)^2 + y (e - e') + (the floor of y e')`, every
  *     term at least 0, so after one step `y` never exceeds `1/b`, and the
  *     error bound is `2 eps^2 + (1 + eps) 2^(drop + 1 - p - fIn) + 2^-fOut`.
  *     Steps are added until `2^(p+1) eps <= 1/2`.
  *  3. `Qc = floor(y 2^(p+1))` then lies within one of `Q` (`|Qc - Q| <= 1`:
  *     `Y = y 2^(p+1)` is within 1/2 of `2^(2p)/B`), and the remainder
  *     `R = 2^(2p) - Qc B` (exact in `p + 3` bits, since `|R| < 2B`) corrects
  *     it: `Q = Qc - 1` when `R < 0`, `Qc + 1` when `R >= B`, else `Qc`; the
  *     division is exact when the corrected remainder is 0.
  *
  * The bounds are computed here in doubles with a factor-of-two margin on the
  * last one; [[soft]] (the hardware's arithmetic in integers) checks every
  * truncation it relies on, and `FpRecipPlanSpec` runs it on every
  * significand of every precision up to FP32's.
  */
case class FpRecipPlan(p: Int, indexBits: Int, tableBits: Int, steps: Seq[FpRecipStep]) {

  /** Fraction bits of the last estimate. */
  def fLast: Int = steps.lastOption.map(_.fOut).getOrElse(tableBits)

  /** The table: for each index, `y0` in units of `2^-tableBits` (at most `2^tableBits`). */
  lazy val table: IndexedSeq[BigInt] = (0 until (1 << indexBits)).map { i =>
    // num / den is 2^tableBits / (the interval's midpoint, or b itself when the index is all of it).
    val (num, den) =
      if (indexBits == p - 1) (BigInt(1) << (tableBits + p - 1), (BigInt(1) << (p - 1)) + i)
      else (BigInt(1) << (tableBits + indexBits + 1), (BigInt(1) << (indexBits + 1)) + 2 * i + 1)
    (2 * num + den) / (2 * den) // to nearest
  }

  /** The index into [[table]] of a normalised significand. */
  def index(b: BigInt): Int = ((b >> (p - 1 - indexBits)) & ((BigInt(1) << indexBits) - 1)).toInt

  /** The estimate's bits: `Qc = floor(y 2^(p+1))` from the last `y`. */
  def quotientShift: Int = fLast - (p + 1)

  /** `(Q, exact)` for a normalised significand `b`, computed as the hardware computes it. */
  def soft(b: BigInt): (BigInt, Boolean) = {
    require(b >> (p - 1) == 1, s"FpRecipPlan($p): $b is not a normalised $p-bit significand")
    var y = table(index(b))
    for (s <- steps) {
      val e = (BigInt(1) << (p - 1 + s.fIn)) - b * y
      val eTrunc = e >> s.drop
      require(eTrunc.bitLength < s.eWidth, s"FpRecipPlan($p): error term $eTrunc of B=$b past ${s.eWidth} bits")
      y = (y << (s.fOut - s.fIn)) + ((y * eTrunc) >> s.productShift(p))
      require(y >= 0 && y.bitLength <= s.fOut + 1, s"FpRecipPlan($p): estimate $y of B=$b past ${s.fOut + 1} bits")
    }
    val qc = y >> quotientShift
    // R = 2^(2p) - Qc B, from the low p + 3 bits of the product (2^(2p) is 0 there; |R| < 2^(p+2)).
    val mask = (BigInt(1) << (p + 3)) - 1
    val low = (-(qc * b)) & mask
    val r = if (low.testBit(p + 2)) low - (mask + 1) else low
    require(r > -b && r < 2 * b, s"FpRecipPlan($p): estimate $qc of B=$b is more than one off")
    if (r < 0) (qc - 1, r + b == 0)
    else if (r >= b) (qc + 1, r - b == 0)
    else (qc, r == 0)
  }
}

object FpRecipPlan {

  /** Table index bits at most: a 256-entry table of about 10 bits is some 40 LUTs. */
  val maxIndexBits = 8

  def apply(p: Int): FpRecipPlan = {
    require(p >= 3, s"FpRecipPlan: precision $p")
    val k = math.min(p - 1, maxIndexBits)
    val whole = k == p - 1
    val m = if (whole) p + 1 else k + 2
    var eps = if (whole) math.pow(2, -(m + 1)) else math.pow(2, -(k + 1)) + math.pow(2, -(m + 1))
    var f = m
    val steps = Seq.newBuilder[FpRecipStep]
    def done = math.pow(2, p + 1) * eps <= 0.5
    var guard = 0
    while (!done) {
      val quad = 2 * eps * eps
      val fOut = math.min(p + 4, math.ceil(-math.log(quad) / math.log(2)).toInt + 2)
      val drop = math.max(0, f + p - 2 - fOut)
      // |E| = |1 - b y| 2^(p-1+f) <= 2 eps 2^(p-1+f); after the shift, one more for the floor and a sign bit.
      val eMag = 2 * eps * math.pow(2, p - 1 + f - drop) + 1
      val eWidth = math.ceil(math.log(eMag) / math.log(2)).toInt + 2
      steps += FpRecipStep(f, fOut, drop, eWidth)
      eps = quad + (1 + eps) * math.pow(2, drop + 1 - p - f) + math.pow(2, -fOut)
      f = fOut
      guard += 1
      require(guard < 8, s"FpRecipPlan($p): no convergence")
    }
    val plan = FpRecipPlan(p, k, m, steps.result())
    require(plan.quotientShift >= 0, s"FpRecipPlan($p): last estimate has ${plan.fLast} fraction bits")
    plan.steps.foreach(s => require(s.productShift(p) >= 0, s"FpRecipPlan($p): step $s"))
    plan
  }
}
