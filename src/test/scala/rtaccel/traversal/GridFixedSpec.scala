package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.{FloatFormat, FpModel}
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.util.Random

/** GridFixed.hw with both roundings (floor and ceil) side by side, for one window. */
class GridFixedHarness(fmt: FloatFormat, kBits: Int, lo: BigInt, hi: BigInt) extends Module {
  private val w = GridFixed.widthOf(lo, hi)
  val io = IO(new Bundle {
    val x = Input(UInt(fmt.width.W))
    val k = Input(SInt(kBits.W))
    val floor = Output(new GridFixed.FixedHw(w))
    val ceil = Output(new GridFixed.FixedHw(w))
  })
  io.floor := GridFixed.hw(fmt, io.x, io.k, up = false, lo, hi)
  io.ceil := GridFixed.hw(fmt, io.x, io.k, up = true, lo, hi)
}

class GridFixedSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "GridFixed.hw"

  /** Drives (x, k) pairs through a harness and compares both roundings with GridFixed.soft bit for bit. */
  private def check(fmt: FloatFormat, kBits: Int, lo: BigInt, hi: BigInt, cases: Iterable[(BigInt, Int)]): Int = {
    var n = 0
    test(new GridFixedHarness(fmt, kBits, lo, hi)).withAnnotations(Backends.treadle) { dut =>
      for ((x, k) <- cases) {
        dut.io.x.poke(x.U)
        dut.io.k.poke(k.S)
        for ((o, up) <- Seq((dut.io.floor, false), (dut.io.ceil, true))) {
          val want = GridFixed.soft(fmt, x, k, up, lo, hi)
          val got = GridFixed.Fixed(o.value.peek().litValue, o.below.peek().litToBoolean, o.above.peek().litToBoolean)
          assert(got == want, s"${fmt.name} x=0x${x.toString(16)} k=$k up=$up window $lo..$hi: hw $got, soft $want")
        }
        n += 1
      }
    }
    n
  }

  it should "equal GridFixed.soft on every e3m3 value, every shift that reaches past both ends, and several windows" in {
    val fmt = FloatFormat(3, 3)
    val xs = BigInt(0) until (BigInt(1) << fmt.width)
    // The shifts that matter lie within about +-(precision + bias + w); +-24 covers them with room.
    val ks = -24 to 24
    val windows =
      Seq((BigInt(0), BigInt(7)), (BigInt(-1), BigInt(5)), (BigInt(-8), BigInt(7)), (BigInt(-4), BigInt(66)))
    for ((lo, hi) <- windows) {
      val n = check(fmt, 7, lo, hi, for (x <- xs; k <- ks) yield (x, k))
      assert(n == xs.size * ks.size)
    }
  }

  it should "equal GridFixed.soft on FP32 in the grid stage's windows: edge values and random ones" in
    Seeded("GridFixedSpec.fp32") { r =>
      val fmt = FloatFormat.FP32
      val p = GridParams()
      def f(x: Float) = FpModel.f32RawBits(x)
      val edges = Seq(
        fmt.zero(false),
        fmt.zero(true),
        fmt.infinity(false),
        fmt.infinity(true),
        fmt.canonicalNaN,
        fmt.canonicalNaN | (BigInt(1) << 31),
        BigInt(1),
        (BigInt(1) << fmt.manBits) - 1,
        BigInt(1) << fmt.manBits,
        fmt.maxFinite(false),
        fmt.maxFinite(true),
        fmt.pack(false, fmt.maxExpField - 1, 0), // trailing zeros and exponent both large
        fmt.pack(false, fmt.maxExpField - 16, BigInt(1) << (fmt.manBits - 1)),
        f(1.0f),
        f(-1.0f),
        f(1.5f),
        f(-0.5f)
      ).flatMap(x => Seq(x, x | (BigInt(1) << 31)))
      // Shifts around each value's thresholds: the window's top, the LSB, and past the precision.
      def randomX(): BigInt = r.nextInt(4) match {
        case 0 => BigInt(r.nextInt(1 << fmt.manBits)) | (BigInt(r.nextInt(2)) << 31) // subnormal or zero
        case 1 => f((r.nextGaussian() * 1e4).toFloat)
        case _ => BigInt(32, r)
      }
      def randomK(x: BigInt, w: Int): Int = {
        val e = fmt.expField(x).max(1) - fmt.bias - fmt.manBits
        r.nextInt(3) match {
          case 0 => -e + r.between(-30, w + 4) // LSB exponent + k near 0..w: the interesting shifts
          case 1 => r.between(-400, 400)
          case _ => -e - fmt.manBits + r.between(-3, w + 3) // the MSB near the window's top
        }
      }
      val windows =
        Seq((BigInt(0), p.stepMax), (p.cLo, p.cHi), (p.gLo, p.gHi), (p.bot, p.top))
      for ((lo, hi) <- windows) {
        val w = GridFixed.widthOf(lo, hi)
        val cases = edges.flatMap(x => (-200 to 200 by 7).map(k => (x, k)) ++ (-160 to -100).map(k => (x, k))) ++
          Seq.fill(6000) { val x = randomX(); (x, randomK(x, w)) }
        val n = check(fmt, 12, lo, hi, cases)
        assert(n == cases.size)
      }
    }
}
