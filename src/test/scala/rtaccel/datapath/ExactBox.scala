package rtaccel.datapath

import rtaccel.fp.FloatFormat

/** The slab test in exact rational arithmetic, for the conservative mode's
  * no-false-miss check: the ray (o, d, tmin, tmax as the datapath holds them,
  * in its format) against the FP32 box, with t = (b - o) / d exactly.
  * None when the case is outside its domain (NaN or infinite box bound or ray
  * component): those are covered by the error and empty-box rules instead.
  */
object ExactBox {

  /** num / den with den > 0. */
  final case class Q(num: BigInt, den: BigInt) {
    def -(o: Q): Q = Q(num * o.den - o.num * den, den * o.den)
    def /(o: Q): Q = if (o.num.signum > 0) Q(num * o.den, den * o.num) else Q(-num * o.den, -den * o.num)
    def cmp(o: Q): Int = (num * o.den).compare(o.num * den)
    def <=(o: Q): Boolean = cmp(o) <= 0
  }

  def value(fmt: FloatFormat, bits: BigInt): Option[Q] =
    if (!fmt.isFinite(bits)) None
    else {
      val e = fmt.lsbExponent(bits)
      val m = if (fmt.sign(bits)) -fmt.significand(bits) else fmt.significand(bits)
      Some(if (e >= 0) Q(m << e, 1) else Q(m, BigInt(1) << -e))
    }

  def hit(
      fmt: FloatFormat,
      o: Seq[BigInt],
      d: Seq[BigInt],
      tmin: BigInt,
      tmax: BigInt,
      bmin: Seq[BigInt],
      bmax: Seq[BigInt]
  ): Option[Boolean] = {
    val f32 = FloatFormat.FP32
    val vo = o.map(value(fmt, _)); val vd = d.map(value(fmt, _))
    val lo = bmin.map(value(f32, _)); val hi = bmax.map(value(f32, _))
    if ((vo ++ vd ++ lo ++ hi).exists(_.isEmpty) || fmt.isNaN(tmin) || fmt.isNaN(tmax) || vd.forall(_.get.num == 0))
      None
    else {
      // Interval of t, None = unbounded on that side.
      // tmin = -inf and tmax = +inf leave that side open (None).
      var near: Option[Q] = value(fmt, tmin)
      var far: Option[Q] = value(fmt, tmax)
      if (fmt.isInfinite(tmin) && !fmt.sign(tmin)) return Some(false)
      if (fmt.isInfinite(tmax) && fmt.sign(tmax)) return Some(false)
      var ok = true
      for (i <- 0 until 3) {
        val (oi, di, a, b) = (vo(i).get, vd(i).get, lo(i).get, hi(i).get)
        if (!(a <= b)) ok = false
        else if (di.num == 0) { if (!(a <= oi && oi <= b)) ok = false }
        else {
          val (t1, t2) = ((a - oi) / di, (b - oi) / di)
          val (l, h) = if (t1 <= t2) (t1, t2) else (t2, t1)
          near = Some(near.fold(l)(n => if (n <= l) l else n))
          far = Some(far.fold(h)(f => if (f <= h) f else h))
        }
      }
      Some(ok && (for (n <- near; f <- far) yield n <= f).getOrElse(true))
    }
  }
}
