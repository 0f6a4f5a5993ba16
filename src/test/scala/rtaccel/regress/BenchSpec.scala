package rtaccel.regress

import org.scalatest.flatspec.AnyFlatSpec

/** `make bench` options and its table, without simulating anything. */
class BenchSpec extends AnyFlatSpec {
  behavior of "Bench"

  it should "parse layouts, runs and the ray cap, and refuse bad ones by name" in {
    val a = Bench.parse(Seq("--layouts", "nori,2,4,8", "--runs", "cornell-box-primary,dragon-ao", "--max-rays", "256"))
    assert(a.layouts == Seq("nori", "2", "4", "8") && a.runs.map(_.name) == Seq("cornell-box-primary", "dragon-ao") && a.maxRays == 256)
    for ((args, word) <- Seq(Seq("--runs", "teapot-primary") -> "'teapot-primary'", Seq("--max-rays", "0") -> "'0'",
        Seq("--layouts", ",") -> "--layouts", Seq("--memory", "ddr") -> "'--memory'")) {
      val e = intercept[IllegalArgumentException](Bench.parse(args))
      assert(e.getMessage.contains(word), e.getMessage)
    }
    assert(Bench.configFor("4").boxLanes == 4 && Bench.configFor("nori").boxLanes == 1)
    val bad = intercept[IllegalArgumentException](Bench.configFor("3"))
    assert(bad.getMessage.contains("'3'") && bad.getMessage.contains("--layouts"), bad.getMessage)
  }

  it should "put layouts (in the order asked for) and memories side by side per run, with box-lane LUTs where known" in {
    def row(run: String, layout: String, memory: String) = ujson.Obj("run" -> run, "layout" -> layout, "memoryKind" -> memory,
      "rays" -> 10, "raySetSize" -> 100, "raysPerCycle" -> 0.05, "efficiency" -> 0.9, "boundLimitedBy" -> "control",
      "nodeTestsPerRay" -> 12.0, "nodeBytesPerRay" -> 384.0, "triangleTestsPerRay" -> 2.0,
      "dramBytesPerRay" -> (if (memory == "ddr") ujson.Num(900) else ujson.Null), "goldenMismatches" -> 0, "embreeMismatches" -> 0)
    val md = BenchMarkdown(Seq(row("dragon-ao", "nori", "ddr"), row("cornell-box-primary", "4", "ddr"),
      row("cornell-box-primary", "4", "onchip"), row("cornell-box-primary", "nori", "onchip")), Map("4" -> 1234.0), 2048, 1)
    val rows = md.linesIterator.filter(_.startsWith("| cornell-box-primary") ).toSeq ++ md.linesIterator.filter(_.startsWith("| dragon")).toSeq
    assert(rows.map(_.split('|').map(_.trim).slice(2, 4).mkString(" ")) == Seq("nori onchip", "4 onchip", "4 ddr", "nori ddr"))
    assert(rows(1).endsWith("| 1234 |") && rows.head.endsWith("| – |"), rows.mkString("\n"))
  }
}
