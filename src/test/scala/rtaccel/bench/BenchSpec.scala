package rtaccel.bench

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.regress.VerilogFigures

/** `make bench` options and its table, without simulating anything. */
class BenchSpec extends AnyFlatSpec {
  behavior of "Bench"

  it should "parse layouts, runs and the ray cap, and refuse bad ones by name" in {
    val a = Bench.parse(Seq("--layouts", "nori,2,4,8", "--runs", "cornell-box-primary,dragon-ao", "--max-rays", "256"))
    assert(a.layouts == Seq("nori", "2", "4", "8") && a.runs.map(_.name) == Seq(
      "cornell-box-primary",
      "dragon-ao"
    ) && a.maxRays == 256)
    for (
      (args, word) <- Seq(
        Seq("--runs", "teapot-primary") -> "'teapot-primary'",
        Seq("--max-rays", "0") -> "'0'",
        Seq("--layouts", ",") -> "--layouts",
        Seq("--memory", "ddr") -> "'--memory'"
      )
    ) {
      val e = intercept[IllegalArgumentException](Bench.parse(args))
      assert(e.getMessage.contains(word), e.getMessage)
    }
    assert(Bench.configFor("4").boxLanes == 4 && Bench.configFor("nori").boxLanes == 1)
    // make bench-quant keeps its own rows and notes: it never redraws make bench's, nor appends its reading.
    val q = Bench.parse(Seq(
      "--out",
      "docs/reports/quant-performance.md",
      "--rows",
      "build/bench/quant.json",
      "--system",
      "0"
    ))
    assert(q.rows.toString == "build/bench/quant.json" && q.system == "0" && Bench.parse(Nil).system == "1")
    assert(Bench.notesFor(q.out).toString == "docs/reports/quant-performance-notes.md" &&
      Bench.notesFor(Bench.parse(Nil).out).toString == "docs/reports/performance-notes.md")
    assert(Bench.parse(Seq("--system", "embree")).system == "embree")
    assert(intercept[IllegalArgumentException](Bench.parse(Seq("--system", "2"))).getMessage.contains("'2'"))
    val bad = intercept[IllegalArgumentException](Bench.configFor("3"))
    assert(bad.getMessage.contains("'3'") && bad.getMessage.contains("--layouts"), bad.getMessage)
  }

  it should "read the cores that fit and the Fmax estimate from make verilog's resources.md, and refuse another configuration" in {
    val dir = java.nio.file.Files.createTempDirectory("bench-spec")
    val f = dir.resolve("resources.md")
    val text = Seq(
      "# Resources: RtAccel e8m23_wt_cons, 4-wide BVH nodes (4 box lanes), 64 ray IDs, stack 64",
      "",
      "Instances that fit on the device (by its scarcest resource): **3**.",
      "",
      "## Fmax estimate per unit (ESTIMATE)",
      "",
      "Estimated system Fmax (slowest unit, **FpAdd_1**): **40 MHz** (25.00 ns)."
    ).mkString("\n")
    java.nio.file.Files.writeString(f, text)
    val want = Seq("RtAccel e8m23_wt_cons,", "(4 box lanes)", "64 ray IDs")
    val v = VerilogFigures.read(f, want)
    assert(v.coresFit == 3 && v.fmaxNs == 25.0 && v.fmaxMhz == 40.0 && v.slowestUnit == "FpAdd_1", v)
    val other = intercept[IllegalArgumentException](VerilogFigures.read(f, Seq("(8 box lanes)")))
    assert(other.getMessage.contains("make verilog") && other.getMessage.contains("(8 box lanes)"), other.getMessage)
    java.nio.file.Files.writeString(f, text.linesIterator.filterNot(_.startsWith("Estimated")).mkString("\n"))
    val noFmax = intercept[IllegalArgumentException](VerilogFigures.read(f, want))
    assert(noFmax.getMessage.contains("Fmax") && noFmax.getMessage.contains(f.toString), noFmax.getMessage)
    assert(intercept[IllegalArgumentException](VerilogFigures.read(dir.resolve("none.md"), want)).getMessage.contains(
      "missing"
    ))
    // With the system top's lines (make verilog's system section), those count: its cores fit beside the
    // system's own units, and its Fmax is the slowest of core and system units.
    java.nio.file.Files.writeString(
      f,
      (text +: Seq(
        "",
        "Cores that fit beside the system's own units (by the scarcest resource): **2**.",
        "",
        "**Estimated Fmax of the system** (its slowest unit, core or system, **MemoryFabric**): **50 MHz** (20.00 ns). An ESTIMATE."
      )).mkString("\n")
    )
    val sys = VerilogFigures.read(f, want)
    assert(sys.coresFit == 2 && sys.fmaxNs == 20.0 && sys.slowestUnit == "MemoryFabric", sys)
    // The system section names its node store: a resources.md made with another size than the default this run
    // builds (NODE_STORE_KIB) is refused, the same size read.
    val kib = rtaccel.system.SystemConfig.defaultNodeStoreBytes / 1024
    java.nio.file.Files.writeString(
      f,
      java.nio.file.Files.readString(f) + s"\nNode store: ${kib + 1} KiB, triangle store: 256 KiB."
    )
    val otherStore = intercept[IllegalArgumentException](VerilogFigures.read(f, want, Some(kib)))
    assert(
      otherStore.getMessage.contains(s"${kib + 1} KiB node store") && otherStore.getMessage.contains("NODE_STORE_KIB"),
      otherStore.getMessage
    )
    java.nio.file.Files.writeString(f, java.nio.file.Files.readString(f).replace(s"${kib + 1} KiB", s"$kib KiB"))
    assert(VerilogFigures.read(f, want, Some(kib)).coresFit == 2)
    // The cores' own block RAM (the DRAM traffic study's budget): the system section's row of its cores, per core.
    val noRow = intercept[IllegalArgumentException](VerilogFigures.coreBram36(f))
    assert(noRow.getMessage.contains("x core (table above)") && noRow.getMessage.contains(f.toString), noRow.getMessage)
    java.nio.file.Files.writeString(
      f,
      text + "\n| 2 x core (table above) | 171,400 | 209,800 | 188 | 87.0 | 2,200 | | | |\n"
    )
    assert(VerilogFigures.coreBram36(f) == 43.5)
  }

  it should "state each throughput goal as met or not and name the term that holds it back" in {
    def row(run: String, cores: Int, rpc: Double) = ujson.Obj(
      "run" -> run,
      "cores" -> cores,
      "rays" -> 100,
      "raySetSize" -> 4096,
      "cycles" -> 100 / rpc,
      "raysPerCycle" -> rpc,
      "nodeStoreHitRate" -> 0.5,
      "dramBytesPerRay" -> 100.0,
      "readBytesPerRay" -> 100.0,
      "readBeatsPerCycle" -> 0.5,
      "goldenMismatches" -> 0,
      "simCyclesPerSecond" -> 1.0,
      "simCyclesPerCpuSecond" -> 1.0
    )
    val r = BenchSystem.Result(
      Seq(
        row("cornell-box-primary", 1, 0.1),
        row("cornell-box-primary", 2, 0.2),
        row("dragon-primary", 1, 0.05),
        row("dragon-primary", 2, 0.1)
      ),
      Map("cornell-box-primary" -> BenchSystem.Embree(50, 40, 2), "dragon-primary" -> BenchSystem.Embree(1, 1, 2)),
      VerilogFigures("t", 2, 1000.0 / 40, "FpAdd"),
      40
    )
    val md = BenchSystemMarkdown(r, 2048)
    // Cornell: 0.2 rays/cycle x 40 MHz = 8 Mrays/s, short of 160 by x20; the clock has x5 of headroom to 200 MHz,
    // the rays/cycle x3.2 (64 B/cycle... at 40 MHz 320 B/cycle, capped at one 64-byte beat: 0.64 rays/cycle).
    assert(md.contains("| cornell-box-primary | 100 of 4096 | 0.1000 | 0.2000 |"), md)
    assert(md.contains("Cornell primary ≥ 160 Mrays/s") && md.contains("**not met**, 8.0 Mrays/s (×20.00 short)"), md)
    assert(md.contains("Held back most by the **clock**") && md.contains("more than one term must move"), md)
    // Dragon: 0.1 x 40 = 4 Mrays/s against 5 x 1 Mrays/s of Embree: not met by x1.25, and the clock alone would do it.
    assert(
      md.contains("**not met**, 4.0 Mrays/s (×1.25 short)") && md.contains(
        "raising it to its ceiling alone would meet the goal"
      ),
      md
    )
    assert(md.contains("estimate, not run on a board") && md.contains("this machine"), md)
    // Every ray set at every core count: DRAM bytes per ray and the R channel's busy share.
    assert(md.contains("| dragon-primary | 2 | 0.1000 | 100 | – | – | – | – | 100 | 0.50 | – |"), md)
    assert(md.contains("Embree's host (`/proc/cpuinfo`): unknown"), md)
  }

  it should "name this host's CPU model and SIMD flags from /proc/cpuinfo, and keep them through the cache" in {
    val f = java.nio.file.Files.createTempFile("cpuinfo", "")
    java.nio.file.Files.writeString(
      f,
      "processor\t: 0\nmodel name\t: Some CPU @ 2.0GHz\nflags\t\t: fpu sse sse2 avx2 fma avx512f ht\n" +
        "processor\t: 1\nmodel name\t: Some CPU @ 2.0GHz\nflags\t\t: fpu sse sse2 avx2 fma avx512f ht\n"
    )
    val h = BenchSystem.host(f)
    assert(h == "Some CPU @ 2.0GHz, 2 CPUs, SIMD flags avx2 avx512f fma sse sse2", h)
    val e = BenchSystem.Embree(10, 5, 2, 0.5, "2026-01-01T00:00:00Z", h)
    val r = BenchSystem.Result(Nil, Map("dragon-primary" -> e), VerilogFigures("t", 2, 10.0, "FpAdd"), 100)
    assert(BenchSystem.fromJson(ujson.read(ujson.write(BenchSystem.toJson(r)))).embree("dragon-primary") == e)
  }

  it should "redraw a cached system section against a newer resources.md, saying where each figure came from, with Embree's load average" in {
    def row(run: String, cores: Int, rpc: Double) = ujson.Obj(
      "run" -> run,
      "cores" -> cores,
      "rays" -> 100,
      "raySetSize" -> 4096,
      "cycles" -> 100 / rpc,
      "raysPerCycle" -> rpc,
      "nodeStoreHitRate" -> 0.5,
      "dramBytesPerRay" -> 100.0,
      "readBytesPerRay" -> 100.0,
      "readBeatsPerCycle" -> 0.5,
      "goldenMismatches" -> 0,
      "simCyclesPerSecond" -> 1.0,
      "simCyclesPerCpuSecond" -> 1.0
    )
    // The bench's own configuration (AccelConfig.zc706's ray IDs): redraw refuses a resources.md of another.
    val title =
      s"RtAccel e8m23_wt_cons, 4-wide BVH nodes (4 box lanes), ${rtaccel.AccelConfig.zc706.numRayIds} ray IDs, stack 64"
    val cached = BenchSystem.Result(
      Seq(row("cornell-box-primary", 1, 0.1), row("cornell-box-primary", 2, 0.2)),
      Map("cornell-box-primary" -> BenchSystem.Embree(50, 40, 2, 1.75, "2026-01-01T00:00:00Z")),
      VerilogFigures(title, 2, 1000.0 / 40, "MemoryFabric"),
      40,
      BenchSystem.Provenance("abc1234", "2026-01-01T00:00:00Z")
    )
    // Through the cache file and back: the load average, the time and the commit survive; an old cache reads as unknown.
    val back = BenchSystem.fromJson(ujson.read(ujson.write(BenchSystem.toJson(cached))))
    assert(back.embree("cornell-box-primary").load1 == 1.75 && back.sim == cached.sim && back.rows == cached.rows, back)
    val old = BenchSystem.toJson(cached); old.obj.remove("commit");
    old("embree")("cornell-box-primary").obj.remove("load1")
    assert(BenchSystem.fromJson(old).sim.commit == "unknown" && BenchSystem.fromJson(old).embree(
      "cornell-box-primary"
    ).load1.isNaN)
    val dir = java.nio.file.Files.createTempDirectory("bench-spec")
    val res = dir.resolve("resources.md")
    def write(fit: Int, ns: Double) = java.nio.file.Files.writeString(
      res,
      Seq(
        s"# Resources: $title",
        "",
        s"Instances that fit on the device (by its scarcest resource): **$fit**.",
        "",
        f"Estimated system Fmax (slowest unit, **MemoryFabric**): **${1000 / ns}%.0f MHz** ($ns%.2f ns)."
      ).mkString("\n")
    )
    val a = Bench.parse(Seq("--verilog", res.toString))
    val dp = rtaccel.datapath.FloatDatapath(
      rtaccel.fp.FloatFormat.FP32,
      rtaccel.datapath.TriangleTest.Watertight,
      rtaccel.datapath.BoxRounding.Conservative
    )
    write(2, 25.0)
    assert(BenchSystem.redraw(a, dp, cached).now.isEmpty, "the same figures: nothing redrawn")
    write(2, 12.5) // a faster system: 80 MHz
    val r = BenchSystem.redraw(a, dp, cached)
    assert(r.estimateMhz == 80 && r.fabricMhz == 40)
    val md = BenchSystemMarkdown(r, 2048)
    assert(
      md.contains("**Redrawn from the cache**") && md.contains("simulated at commit abc1234") && md.contains(
        "clocked at 40 MHz"
      ),
      md
    )
    assert(
      md.contains("| 16.0 (= 2 × 0.1000 rays/cycle per core × 80 MHz) | 50.0 | 1.75 | 2026-01-01T00:00:00Z | 0.32 |"),
      md
    )
    write(3, 12.5) // three cores fit now, and the cache has no 3-core rows
    val e = intercept[IllegalArgumentException](BenchSystem.redraw(a, dp, cached))
    assert(e.getMessage.contains("3 cores fit") && e.getMessage.contains("make bench"), e.getMessage)
    // Another system (BVH=4q BOX_TEST=grid): its own cache file, and a cache of one system never redraws the other's.
    val grid = Bench.parse(Seq("--verilog", res.toString, "--system-layout", "4q", "--box-test", "grid"))
    assert(BenchSystem.cacheFile(a) == Bench.root.resolve("system.json"))
    assert(BenchSystem.cacheFile(grid) == Bench.root.resolve("system-4q-grid.json"))
    assert(BenchSystem.makeVars("4q", "grid") == " BVH=4q BOX_TEST=grid" && BenchSystem.makeVars("4", "fp32") == "")
    val wrong = intercept[IllegalArgumentException](BenchSystem.redraw(grid, dp, cached))
    assert(wrong.getMessage.contains("4 nodes with fp32") && wrong.getMessage.contains("BOX_TEST="), wrong.getMessage)
    val gridCached = BenchSystem.fromJson(ujson.read(ujson.write(BenchSystem.toJson(cached.copy(
      layout = "4q",
      boxTest = "grid"
    )))))
    assert(gridCached.layout == "4q" && gridCached.boxTest == "grid")
    // The default resources.md is not the grid system's: its title names the layout and the box unit.
    val notGrid = intercept[IllegalArgumentException](BenchSystem.redraw(grid, dp, gridCached))
    assert(notGrid.getMessage.contains("4q (quantized 4-wide) BVH nodes (4 grid box lanes)"), notGrid.getMessage)
    assert(BenchSystemMarkdown.coresNote(gridCached) ==
      "4q (quantized 4-wide nodes of 64 bytes, child boxes tested in the node's grid: docs/kernels.md)")
    assert(BenchSystemMarkdown.coresNote(cached) == "4-wide")
  }

  it should "put layouts (in the order asked for) and memories side by side per run, with box-lane LUTs where known" in {
    def row(run: String, layout: String, memory: String) = ujson.Obj(
      "run" -> run,
      "layout" -> layout,
      "memoryKind" -> memory,
      "rays" -> 10,
      "raySetSize" -> 100,
      "raysPerCycle" -> 0.05,
      "efficiency" -> 0.9,
      "boundLimitedBy" -> "control",
      "nodeTestsPerRay" -> 12.0,
      "nodeBytesPerRay" -> 384.0,
      "triangleTestsPerRay" -> 2.0,
      "dramBytesPerRay" -> (if (memory == "ddr") ujson.Num(900) else ujson.Null),
      "goldenMismatches" -> 0,
      "embreeMismatches" -> 0
    )
    val md = BenchMarkdown(
      Seq(
        row("dragon-ao", "nori", "ddr"),
        row("cornell-box-primary", "4", "ddr"),
        row("cornell-box-primary", "4", "onchip"),
        row("cornell-box-primary", "nori", "onchip")
      ),
      Map("4" -> 1234.0),
      2048,
      1
    )
    val rows = md.linesIterator.filter(_.startsWith("| cornell-box-primary")).toSeq ++ md.linesIterator.filter(
      _.startsWith("| dragon")
    ).toSeq
    assert(rows.map(_.split('|').map(_.trim).slice(2, 4).mkString(" ")) == Seq(
      "nori onchip",
      "4 onchip",
      "4 ddr",
      "nori ddr"
    ))
    assert(rows(1).endsWith("| 1234 |") && rows.head.endsWith("| – |"), rows.mkString("\n"))
  }

  "EmitVerilog.coreTitle" should "keep the default system's title and name the quantized layout and the grid box test" in {
    val cfg = rtaccel.AccelConfig.zc706
    val ids = cfg.numRayIds
    assert(
      rtaccel.tools.EmitVerilog.coreTitle("e8m23_wt_cons", cfg) ==
        s"RtAccel e8m23_wt_cons, 4-wide BVH nodes (4 box lanes), $ids ray IDs"
    )
    val q = cfg.copy(layout = rtaccel.bvh.BvhLayout.Wide(4, quantized = true), boxTest = rtaccel.BoxTest.Grid)
    assert(
      rtaccel.tools.EmitVerilog.coreTitle("e8m23_wt_cons", q) ==
        s"RtAccel e8m23_wt_cons, 4q (quantized 4-wide) BVH nodes (4 grid box lanes), $ids ray IDs"
    )
  }
}
