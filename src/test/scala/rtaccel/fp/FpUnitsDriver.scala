package rtaccel.fp

import chisel3._
import chisel3.util.Valid
import chiseltest._

import scala.collection.mutable

/** Streams vectors into an [[FpUnitsHarness]], one per cycle (II = 1), and
  * checks every output `latency` cycles later against the golden model (and,
  * for FP32 RNE, against JVM `Float`). Directed modes are also checked against
  * the exact value: RDN <= exact, RUP >= exact. Single-threaded poke/peek/step.
  */
object FpUnitsDriver {
  private val F32 = FloatFormat.FP32
  private def hex(x: BigInt) = "0x" + x.toString(16)

  /** One checked output: its latency, how to read it, and its expected value. */
  private case class Port(
      name: String,
      latency: Int,
      read: FpUnitsHarness => (Boolean, BigInt),
      expect: FpVector => BigInt
  )

  /** Runs `vectors` and returns the number of checked results per port; throws on the first mismatch. */
  def run(dut: FpUnitsHarness, vectors: IndexedSeq[FpVector], jvmCheck: Boolean): Map[String, Int] = {
    import FpModel._
    val fmt = dut.fmt
    val lat = dut.lat
    def v(x: Valid[UInt]) =
      (x.valid.peek().litToBoolean, if (x.valid.peek().litToBoolean) x.bits.peek().litValue else BigInt(0))
    def cmpWord(r: FpVector) = { // lt | eq | unordered | min | max packed for one comparison
      val bits =
        Seq(lt(fmt, r.a, r.b), equal(fmt, r.a, r.b), unordered(fmt, r.a, r.b)).map(b => if (b) BigInt(1) else BigInt(0))
      (((bits(0) << 2) | (bits(1) << 1) | bits(2)) << (2 * fmt.width)) | (min(fmt, r.a, r.b) << fmt.width) | max(
        fmt,
        r.a,
        r.b
      )
    }
    val ports = Seq(
      Port("add", lat.add, d => v(d.io.add), r => add(fmt, r.rm, r.a, r.b)),
      Port("sub", lat.add, d => v(d.io.sub), r => sub(fmt, r.rm, r.a, r.b)),
      Port("mul", lat.mul, d => v(d.io.mul), r => mul(fmt, r.rm, r.a, r.b)),
      Port("div", lat.div, d => v(d.io.div), r => div(fmt, r.rm, r.a, r.b)),
      Port("recip", lat.recip, d => v(d.io.recip), r => recip(fmt, r.rm, r.a)),
      Port(
        "cmp",
        lat.cmp,
        { d =>
          val c = d.io.cmp
          val ok = c.valid.peek().litToBoolean
          if (!ok) (false, BigInt(0))
          else {
            val flags =
              Seq(c.bits.lt, c.bits.eq, c.bits.unordered).map(x => if (x.peek().litToBoolean) BigInt(1) else BigInt(0))
            (
              true,
              (((flags(0) << 2) | (flags(1) << 1) | flags(
                2
              )) << (2 * fmt.width)) | (c.bits.min.peek().litValue << fmt.width) | c.bits.max.peek().litValue
            )
          }
        },
        cmpWord
      ),
      Port("fromF32", lat.conv, d => v(d.io.fromF32), r => fromFloat32(fmt, r.rm, r.f32)),
      Port("toF32", lat.conv, d => v(d.io.toF32), r => toFloat32(fmt, r.rm, r.a))
    )
    val checked = mutable.Map.empty[String, Int].withDefaultValue(0)
    val maxLat = ports.map(_.latency).max
    dut.io.in.valid.poke(false.B)
    for (cycle <- 0 until vectors.size + maxLat) {
      if (cycle < vectors.size) {
        val r = vectors(cycle)
        dut.io.in.valid.poke(r.valid.B)
        dut.io.in.bits.a.poke(r.a.U)
        dut.io.in.bits.b.poke(r.b.U)
        dut.io.in.bits.rm.foreach(_.poke(r.rm.code.U))
        dut.io.f32.poke(r.f32.U)
      } else dut.io.in.valid.poke(false.B)
      for (port <- ports) {
        val idx = cycle - port.latency
        if (idx >= 0 && idx < vectors.size) {
          val r = vectors(idx)
          val (valid, got) = port.read(dut)
          def where = s"${fmt.name} ${port.name} vector $idx (a=${hex(r.a)} b=${hex(r.b)} f32=${hex(r.f32)} rm=${r.rm})"
          assert(valid == r.valid, s"$where: out.valid=$valid, expected ${r.valid} (latency ${port.latency})")
          if (r.valid) {
            val want = port.expect(r)
            assert(got == want, s"$where: got ${hex(got)}, model ${hex(want)}")
            if (jvmCheck && r.rm == RoundingMode.RNE) checkJvm(port.name, r, got, where)
            checkDirected(fmt, port.name, r, got, where)
            checked(port.name) += 1
          }
        }
      }
      dut.clock.step()
    }
    checked.toMap
  }

  /** FP32 RNE results vs JVM Float, all NaNs equal (`f32Bits`). */
  private def checkJvm(port: String, r: FpVector, got: BigInt, where: => String): Unit = {
    import FpModel.{f32, f32Bits}
    val (x, y) = (f32(r.a), f32(r.b))
    val want: Option[Float] = port match {
      case "add"   => Some(x + y)
      case "sub"   => Some(x - y)
      case "mul"   => Some(x * y)
      case "div"   => Some(x / y)
      case "recip" => Some(1f / x)
      case _       => None
    }
    want.foreach(w => assert(got == f32Bits(w), s"$where: got ${hex(got)}, JVM Float ${hex(f32Bits(w))}"))
  }

  /** RDN results never above the exact value, RUP never below (finite exact values only). */
  private def checkDirected(fmt: FloatFormat, port: String, r: FpVector, got: BigInt, where: => String): Unit = {
    if (r.rm != RoundingMode.RDN && r.rm != RoundingMode.RUP) return
    def fin(x: BigInt) = fmt.isFinite(x)
    def value(x: BigInt) = FpExact.value(fmt, x)
    val exact: Option[Rational] = port match {
      case "add" if fin(r.a) && fin(r.b)                     => Some(value(r.a) + value(r.b))
      case "sub" if fin(r.a) && fin(r.b)                     => Some(value(r.a) - value(r.b))
      case "mul" if fin(r.a) && fin(r.b)                     => Some(value(r.a) * value(r.b))
      case "div" if fin(r.a) && fin(r.b) && !fmt.isZero(r.b) => Some(value(r.a) / value(r.b))
      case "recip" if fin(r.a) && !fmt.isZero(r.a)           => Some(Rational(1, 1) / value(r.a))
      case "fromF32" if F32.isFinite(r.f32)                  => Some(FpExact.value(F32, r.f32))
      case _                                                 => None
    }
    exact.foreach { e =>
      assert(!fmt.isNaN(got), s"$where: NaN for a finite exact value")
      val ok =
        if (fmt.isInfinite(got)) fmt.sign(got) == (r.rm == RoundingMode.RDN)
        else if (r.rm == RoundingMode.RDN) value(got) <= e
        else value(got) >= e
      assert(ok, s"$where: ${r.rm} result ${hex(got)} is on the wrong side of the exact value")
    }
  }
}
