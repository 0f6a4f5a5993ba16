package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec

/** The Fmax estimate's arithmetic and its reading of Yosys's `ltp` output (no Yosys run). */
class FmaxEstimateSpec extends AnyFlatSpec {
  private val m = DelayModel.zynq7

  "DelayModel.pathNs" should "charge clock-to-out, setup, and a routed hop before a lone LUT" in {
    assert(math.abs(m.pathNs(Seq("LUT6")) - (m.tcko + m.setup + m.net + m.lut)) < 1e-9)
  }

  it should "route nothing inside a slice: LUT into CARRY4 or MUXF7, MUXF7 into MUXF8, along a carry chain" in {
    val chain = Seq("LUT2", "CARRY4", "CARRY4", "CARRY4")
    val expect = m.tcko + m.setup + m.net + m.lut + m.carryIn + 2 * m.carryBypass + m.carryOut
    assert(math.abs(m.pathNs(chain) - expect) < 1e-9)
    val wide = Seq("LUT6", "MUXF7", "MUXF8", "LUT3")
    assert(math.abs(m.pathNs(wide) - (m.tcko + m.setup + 2 * m.net + 2 * m.lut + m.muxf7 + m.muxf8)) < 1e-9)
  }

  it should "enter a carry chain anew after another cell, and leave it through CI->O" in {
    // The first chain is routed to from the register, the LUT from the chain; the LUT feeds its own slice's chain.
    val twoChains = Seq("CARRY4", "LUT1", "CARRY4")
    val expect = m.tcko + m.setup + 2 * m.net + m.lut + 2 * (m.carryIn + m.carryOut)
    assert(math.abs(m.pathNs(twoChains) - expect) < 1e-9)
  }

  it should "treat an inverter as absorbed into the cell it feeds (no delay, no hop)" in {
    assert(math.abs(m.pathNs(Seq("LUT6", "INV", "CARRY4")) - m.pathNs(Seq("LUT6", "CARRY4"))) < 1e-9)
  }

  private val log =
    """Longest topological path in Top (length=4):
      |    0: \a [3]
      |    1: $abc$1.f0 (via cLUT6_0)
      |    2: $abc$2.f0 (via cMUXF7_12)
      |    3: $auto$alu.CO [3] (via cCARRY4_7)
      |    4: \b (via $flatten\x.$abc$9)
      |
      |End of script.
      |""".stripMargin

  "FmaxEstimate.parsePath" should "read the cell types ltp printed, in order, unnamed cells as other" in {
    val p = FmaxEstimate.parsePath(log, "test.log")
    assert(p.cells == Seq("LUT6", "MUXF7", "CARRY4", "other"))
    assert((p.luts, p.muxf, p.carry4, p.other) == ((1, 1, 1, 1)))
  }

  it should "refuse a log whose path length disagrees with the cells it lists" in {
    val bad = log.replace("length=4", "length=5")
    val e = intercept[IllegalArgumentException](FmaxEstimate.parsePath(bad, "bad.log"))
    assert(e.getMessage.contains("bad.log"))
  }

  it should "refuse a log without a path, naming the file" in {
    val e = intercept[IllegalArgumentException](FmaxEstimate.parsePath("nothing", "empty.log"))
    assert(e.getMessage.contains("empty.log"))
  }

  it should "read both ltp runs and keep the slower path, not the one with more cells" in {
    // The first run (carry chains kept) reports nine cells of a carry chain; the second (CARRY4 cut) five LUTs.
    val chain = (Seq("    0: \\r [0]", "    1: $a.X (via cLUT2_1)") ++
      (2 to 9).map(i => s"    $i: $$a.CO [$i] (via cCARRY4_$i)")).mkString("\n")
    val luts = (Seq("    0: \\s [0]") ++ (1 to 5).map(i => s"    $i: $$b.f$i (via cLUT6_$i)")).mkString("\n")
    val two =
      s"Longest topological path in Top (length=9):\n$chain\n\nLongest topological path in Top (length=5):\n$luts\n\nEnd of script.\n"
    val paths = FmaxEstimate.parsePaths(two, "two.log")
    assert(paths.map(_.cells.size) == Seq(9, 5))
    assert(m.pathNs(paths(1).cells) > m.pathNs(paths(0).cells), "the fixture's LUT path must be the slower")
    assert(FmaxEstimate.slowest(paths, m) == paths(1))
  }

  "FmaxEstimate.units" should "list FP and datapath units alone, other modules with the datapath black-boxed, and skip plumbing" in {
    def mod(name: String, insts: String*) =
      s"module $name(\n  input a\n);\n" + insts.map(i => s"  $i u_$i (\n    .a (a)\n  );\n").mkString + "endmodule\n\n"
    val sv = mod("FpAdd_e8m23_rne_l7") + mod("BoxLane_x", "FpAdd_e8m23_rne_l7") + mod("ram_64x6") +
      mod("Queue64_T", "ram_64x6") + mod("Ctl", "BoxLane_x", "Queue64_T") + mod("Top", "Ctl")
    val us = FmaxEstimate.units(sv, "Top")
    assert(us == Seq(
      ("FpAdd_e8m23_rne_l7", "FpAdd_e8m23_rne_l7", Nil),
      ("BoxLane_x", "BoxLane_x", Nil),
      ("Ctl", "Ctl", Seq("BoxLane_x")),
      ("Top (control)", "Top", Seq("BoxLane_x"))
    ))
  }

  "FmaxEstimate.units" should "synthesise the grid box unit whole and black-box it in the control, as it does the box lanes" in {
    def mod(name: String, insts: String*) =
      s"module $name(\n  input clock\n);\n" + insts.zipWithIndex.map { case (m, i) =>
        s"  $m u_$i (\n  );\n"
      }.mkString +
        "endmodule\n"
    val sv = Seq(
      mod("FpAdd_e8m23_rdn_l7"),
      mod("GridLane_q8"),
      mod("GridNodeStage_q8", "FpAdd_e8m23_rdn_l7"),
      mod("GridBboxIntersect_k4_q8", "GridNodeStage_q8", "GridLane_q8"),
      mod("PrimIntersect_e8m23_wt_cons", "FpAdd_e8m23_rdn_l7"),
      mod("Traversal_k4", "GridBboxIntersect_k4_q8"),
      mod("RtAccel_top", "Traversal_k4", "PrimIntersect_e8m23_wt_cons")
    ).mkString
    val u = FmaxEstimate.units(sv, "RtAccel_top").map(x => x._2 -> x._3).toMap
    assert(u.keySet == Set(
      "FpAdd_e8m23_rdn_l7",
      "GridBboxIntersect_k4_q8",
      "PrimIntersect_e8m23_wt_cons",
      "Traversal_k4",
      "RtAccel_top"
    ))
    assert(u("GridBboxIntersect_k4_q8").isEmpty)
    assert(u("Traversal_k4") == Seq("GridBboxIntersect_k4_q8"))
    assert(u("RtAccel_top").toSet == Set("GridBboxIntersect_k4_q8", "PrimIntersect_e8m23_wt_cons"))
  }

  "SystemArea.markdown" should "never state more cores than the system it measured was built with" in {
    // A core of 68k LUT beside units of 14k LUT and 285 BRAM36 (a 1-core system): by LUT three would fit, but a
    // third core doubles the stores (570 BRAM36), so the page states only what it measured.
    val core = Synth.Area(68000, 110000, 0, 106, 0, 0, 0, 0)
    val own = Synth.Area(14000, 6000, 0, 0, 0, 285, 0, 0)
    assert(SystemArea.coresThatFit(core, own, EmitVerilog.Zc706) == 3)
    // The units' LUTs used as memory count against the device's LUTs: 14k + 10k leave room for two.
    assert(SystemArea.coresThatFit(core, own.copy(lutram = 10000), EmitVerilog.Zc706) == 2)
    val row = FmaxEstimate.Row("NodeStore", "NodeStore", own, FmaxEstimate.PathCells(Seq("LUT6")), 2.0)
    def fitLine(cores: Int) =
      SystemArea.markdown(Seq(row), cores, core, EmitVerilog.Zc706, 1 << 20).linesIterator.find(
        _.startsWith("Cores that fit")
      )
    assert(fitLine(1).contains("Cores that fit beside the system's own units (by the scarcest resource): **1**."))
    assert(fitLine(2).get.contains("**2**"))
    // Past the device: what the units leave holds fewer cores than were built.
    val big = row.copy(area = own.copy(ramb36 = 570))
    assert(SystemArea.markdown(Seq(big), 3, core, EmitVerilog.Zc706, 1 << 20).contains(
      "system's own units (by the scarcest resource): **0**."
    ))
  }
}
