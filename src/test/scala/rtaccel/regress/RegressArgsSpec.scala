package rtaccel.regress

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.mem.{Latency, MemoryKind}

/** `make regress` options: the defaults it documents, and an error naming
  * the option and the value for every bad one.
  */
class RegressArgsSpec extends AnyFlatSpec {
  behavior of "RegressArgs"

  private val base = Seq("--package", "p", "--out", "o")
  private def parse(kv: String*) = RegressArgs.parse(base ++ kv)

  it should "default to conservative boxes and the ZC706 DDR3 at 200 MHz, 100 ns = 20 cycles" in {
    val a = parse()
    assert(a.rounding == "conservative" && a.memoryKind == MemoryKind.Ddr())
    assert(a.environment.node.latency == Latency.Fixed(20) && a.environment.memory == MemoryKind.Ddr())
    assert(a.environment.node.seed != a.environment.tri.seed, "the ports draw from their own seeds")
  }

  it should "convert --mem-latency from ns at --fabric-mhz, and fix on-chip latency at 2 cycles" in {
    assert(parse("--mem-latency", "80-300").port(0).latency == Latency.Uniform(16, 60))
    val slow = parse("--mem-latency", "100", "--fabric-mhz", "125")
    assert(slow.port(0).latency == Latency.Fixed(13) && slow.memoryKind == MemoryKind.Ddr(slow.clock))
    val on = parse("--memory", "onchip")
    assert(on.memoryKind == MemoryKind.OnChip && on.port(1).latency == Latency.Fixed(2))
  }

  it should "refuse every bad value with a message naming the option and the value" in {
    val bad = Seq(
      Seq("--memory", "sram") -> Seq("--memory", "'sram'"),
      Seq("--mem-latency", "300-80") -> Seq("--mem-latency", "'300-80'"),
      Seq("--mem-latency", "fast") -> Seq("--mem-latency", "'fast'"),
      Seq("--fabric-mhz", "0") -> Seq("--fabric-mhz", "'0'"),
      Seq("--fabric-mhz", "x") -> Seq("--fabric-mhz", "'x'"),
      Seq("--outstanding", "0") -> Seq("--outstanding", "'0'"),
      Seq("--bytes-per-cycle", "16") -> Seq("--bytes-per-cycle"),
      Seq("--memory", "onchip", "--mem-latency", "100") -> Seq("--mem-latency", "100 ns", "onchip"),
      Seq("--memory", "onchip", "--cache", "32") -> Seq("--cache", "on-chip"),
      Seq("--box-test", "int8") -> Seq("--box-test", "'int8'")
    )
    for ((args, words) <- bad) {
      val e = intercept[IllegalArgumentException](parse(args: _*))
      val first = e.getMessage.linesIterator.next()
      for (w <- words) assert(first.contains(w), s"${args.mkString(" ")}: '$first' does not name $w")
    }
  }

  it should "accept grid box tests only with a quantized layout and FP32 boxes, naming the option and the value" in {
    import rtaccel.{AccelConfig, BoxTest}
    import rtaccel.bvh.BvhLayout
    assert(parse("--box-test", "grid").boxTest == "grid" && parse().boxTest == "fp32")
    assert(AccelConfig(layout = BvhLayout.Wide(8, quantized = true), boxTest = BoxTest.Grid).gridBox)
    for (layout <- Seq(BvhLayout.Nori, BvhLayout.Wide(4))) {
      val e = intercept[IllegalArgumentException](AccelConfig(layout = layout, boxTest = BoxTest.Grid))
      assert(e.getMessage.contains("boxTest = grid") && e.getMessage.contains(layout.name), e.getMessage)
    }
    val e = intercept[IllegalArgumentException](
      AccelConfig(layout = BvhLayout.Wide(4, quantized = true), boxTest = BoxTest.Grid)
        .withFloat(rtaccel.fp.FloatFormat(8, 10))
    )
    assert(e.getMessage.contains("boxTest = grid") && e.getMessage.contains("e8m10"), e.getMessage)
  }
}
