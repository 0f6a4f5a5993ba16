package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec

/** AccelArea's Verilog slicing: which modules each per-unit Yosys run reads. */
class AccelAreaSpec extends AnyFlatSpec {
  private val sv =
    """module Leaf(
      |  input a
      |);
      |endmodule
      |
      |module Mid(
      |  input a
      |);
      |  Leaf leaf (
      |    .a (a)
      |  );
      |endmodule
      |
      |module Other(
      |  input a
      |);
      |endmodule
      |
      |module Top(
      |  input a
      |);
      |  Mid mid (
      |    .a (a)
      |  );
      |  Other other (
      |    .a (a)
      |  );
      |endmodule
      |""".stripMargin

  "AccelArea.modules" should "split emitted Verilog into whole modules, in order" in {
    val mods = AccelArea.modules(sv)
    assert(mods.map(_.name) == Seq("Leaf", "Mid", "Other", "Top"))
    assert(mods.map(_.text).mkString == sv.replace("endmodule\n\n", "endmodule\n"))
  }

  "AccelArea.subtree" should "follow instances transitively and leave out the rest" in {
    val mods = AccelArea.modules(sv)
    assert(AccelArea.subtree(mods, "Mid").map(_.name) == Seq("Leaf", "Mid"))
    assert(AccelArea.subtree(mods, "Top").map(_.name) == Seq("Leaf", "Mid", "Other", "Top"))
    assertThrows[IllegalArgumentException](AccelArea.subtree(mods, "Missing"))
  }

  "AccelArea.instances" should "count whole instances by the scarcest resource" in {
    val a = Synth.Area(lut = 60000, ff = 1000, srl = 0, dsp = 100, carry = 0, ramb36 = 1, ramb18 = 1, lutram = 0)
    assert(AccelArea.instances(a, EmitVerilog.Zc706) == 3) // 218,600 / 60,000 LUT
    assert(AccelArea.instances(a.copy(dsp = 400), EmitVerilog.Zc706) == 2) // 900 / 400 DSP
    // LUTs used as memory take device LUTs too: 50,000 + 25,000 of 218,600.
    assert(AccelArea.instances(a.copy(lut = 50000, lutram = 25000), EmitVerilog.Zc706) == 2)
    // ... and only the SLICEM LUTs can hold memory: 70,400 / 40,000.
    assert(AccelArea.instances(a.copy(lut = 10000, lutram = 30000, srl = 10000), EmitVerilog.Zc706) == 1)
  }

  "Synth.parseTotal" should "count distributed RAM and shift registers in LUT sites" in {
    val log =
      """Number of cells: 99
        |     LUT6                          100
        |     FDRE                           50
        |     RAM64M                          3
        |     RAM64X1D                        2
        |     RAM32X1S                        5
        |     SRL16E                          7
        |     RAMB36E1                        1
        |""".stripMargin
    val a = Synth.parseTotal(log, java.nio.file.Path.of("unit.log"))
    assert(a.lut == 100 && a.ff == 50 && a.ramb36 == 1)
    assert(a.lutram == 3 * 4 + 2 * 2 + 5 * 1)
    assert(a.lutMemory == 21 + 7)
    assert(a.lutSites == 128)
    val odd = intercept[IllegalArgumentException](Synth.parseTotal(
      log + "     RAM512X1S   1\n",
      java.nio.file.Path.of("unit.log")
    ))
    assert(odd.getMessage.contains("unit.log") && odd.getMessage.contains("RAM512X1S"), odd.getMessage)
  }

  "ResourceTable" should "count LUTs used as memory in the LUTs, and state the device's LUTs and SLICEM LUTs" in {
    val control = Synth.Area(lut = 9000, ff = 100, srl = 4, dsp = 0, carry = 0, ramb36 = 20, ramb18 = 47, lutram = 1088)
    val md = ResourceTable("t", Seq("control" -> control), EmitVerilog.Zc706, 0)
    assert(md.contains("| control | 10,092 | 1,092 | 100 | 0 | 43.5 | 0 |"), md)
    assert(md.contains("| ZC706 (xc7z045) capacity | 218,600 | 70,400 |"), md)
    assert(md.contains("| share of the device | 4.6% | 1.6% |"), md)
  }
}
