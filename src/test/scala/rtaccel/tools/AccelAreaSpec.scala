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
  }
}
