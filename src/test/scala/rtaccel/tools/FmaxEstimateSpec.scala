package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec

/** The Fmax estimate's delay model and its timing pass over hand-written Yosys JSON netlists (no Yosys run). */
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

  // A hand-written Yosys JSON netlist: bit 1 is the clock, every other bit an int of the caller's; unconnected
  // carry outputs take fresh bits from 1000 up. Nets are named n<bit>.
  private type Pins = Seq[(String, Seq[Any])]
  private var fresh = 1000
  private def spare(n: Int) = (0 until n).map { _ => fresh += 1; fresh }
  private def ff(name: String, d: Int, q: Int) =
    ("FDRE", name, Seq("C" -> Seq(1), "D" -> Seq(d), "Q" -> Seq(q), "CE" -> Seq("1"), "R" -> Seq("0")))
  private def lut(name: String, ins: Seq[Int], o: Int) =
    (s"LUT${ins.size}", name, ins.zipWithIndex.map { case (b, i) => s"I$i" -> Seq[Any](b) } :+ ("O" -> Seq(o)))
  private def carry(name: String, ci: Any, s: Seq[Any], o: Seq[Any] = spare(4), co: Seq[Any] = spare(4)) =
    (
      "CARRY4",
      name,
      Seq("CI" -> Seq(ci), "CYINIT" -> Seq("0"), "DI" -> Seq("0", "0", "0", "0"), "S" -> s, "O" -> o, "CO" -> co)
    )
  private def mux(t: String, name: String, i0: Int, i1: Int, sel: Int, o: Int) =
    (t, name, Seq("I0" -> Seq(i0), "I1" -> Seq(i1), "S" -> Seq(sel), "O" -> Seq(o)))
  // LUT -> MUXF7 -> MUXF8 from bit `in` to bit in + 3, the muxes selected by `sel`.
  private def wideLevel(name: String, in: Int, sel: Int) = Seq(
    lut(s"${name}_lut", Seq(in), in + 1),
    mux("MUXF7", s"${name}_f7", in + 1, in + 1, sel, in + 2),
    mux("MUXF8", s"${name}_f8", in + 2, in + 2, sel, in + 3)
  )
  private def isOut(t: String, p: String) =
    Set("Q", "O", "CO", "SPO", "DPO", "P", "PCOUT")(p) || (t.startsWith("RAM") && p.startsWith("DO"))
  private def netlist(cells: (String, String, Pins)*): ujson.Value = {
    def bits(v: Seq[Any]) = ujson.Arr.from(v.map {
      case i: Int    => ujson.Num(i)
      case s: String => ujson.Str(s)
    })
    val used = cells.flatMap(_._3.flatMap(_._2)).collect { case i: Int => i }.distinct
    ujson.Obj("modules" -> ujson.Obj("top" -> ujson.Obj(
      "ports" -> ujson.Obj("clock" -> ujson.Obj("direction" -> "input", "bits" -> ujson.Arr(1))),
      "cells" -> ujson.Obj.from(cells.map { case (t, name, pins) =>
        name -> ujson.Obj(
          "type" -> t,
          "port_directions" -> ujson.Obj.from(pins.map { case (p, _) =>
            p -> ujson.Str(if (isOut(t, p)) "output" else "input")
          }),
          "connections" -> ujson.Obj.from(pins.map { case (p, v) => p -> bits(v) })
        )
      }),
      "netnames" -> ujson.Obj.from(used.map(b => s"n$b" -> ujson.Obj("hide_name" -> 0, "bits" -> ujson.Arr(b))))
    )))
  }
  private def longest(cells: (String, String, Pins)*) = TimingGraph.longest(netlist(cells: _*), "top", m)

  "TimingGraph.longest" should "find a mixed LUT and carry path with fewer cells than the longest by count, with or without carry chains" in {
    val chain = Seq(ff("a", 2, 10), lut("c0", Seq(10), 11)) ++ (0 until 10).map { i =>
      carry(
        s"k$i",
        if (i == 0) "0" else 100 + i - 1,
        Seq(if (i == 0) 11 else "1", "1", "1", "1"),
        co = Seq(spare(3): _*) :+ (100 + i)
      )
    } ++ Seq(carry("k10", 109, Seq("1", "1", "1", "1"), o = 12 +: spare(3)), ff("b", 12, 13))
    // Two LUT -> MUXF7 -> MUXF8 levels: six cells, fewer than the chain's; the longest path without carry chains.
    val wide = (ff("c", 2, 20) +: wideLevel("w0", 20, 20)) ++ wideLevel("w1", 23, 20) :+ ff("d", 26, 27)
    // LUT, carry, LUT, carry: four cells, slower than either.
    val mixed = Seq(
      ff("e", 2, 30),
      lut("x0", Seq(30), 31),
      carry("x1", "0", Seq(31, "1", "1", "1"), o = 32 +: spare(3)),
      lut("x2", Seq(32), 33),
      carry("x3", "0", Seq(33, "1", "1", "1"), o = 34 +: spare(3)),
      ff("f", 34, 35)
    )
    val chainCells = "LUT1" +: Seq.fill(11)("CARRY4")
    val wideCells = Seq("LUT1", "MUXF7", "MUXF8", "LUT1", "MUXF7", "MUXF8")
    val byCountNs = m.pathNs(chainCells) max m.pathNs(wideCells)
    val p = longest(chain ++ wide ++ mixed: _*)
    assert(p.cells == Seq("LUT1", "CARRY4", "LUT1", "CARRY4"))
    assert(p.cells.size < wideCells.size && wideCells.size < chainCells.size)
    assert(math.abs(p.ns - m.pathNs(p.cells)) < 1e-9)
    assert(p.ns > byCountNs + 0.3, s"${p.ns} against the paths by count's $byCountNs")
    assert((p.from, p.to) == (("n30", "n35")))
  }

  it should "price a chain as DelayModel.pathNs prices its cell list" in {
    // LUT into S of the first slice, CO[3] into CI twice, out of the last slice's O[2].
    val carryChain = longest(
      ff("a", 2, 10),
      lut("l", Seq(10, 10), 11),
      carry("k0", "0", Seq("1", "1", "1", 11), co = spare(3) :+ 12),
      carry("k1", 12, Seq("1", "1", "1", "1"), co = spare(3) :+ 13),
      carry("k2", 13, Seq("1", "1", "1", "1"), o = Seq(spare(2)(0), spare(1)(0), 14, spare(1)(0))),
      ff("b", 14, 15)
    )
    assert(carryChain.cells == Seq("LUT2", "CARRY4", "CARRY4", "CARRY4"))
    assert(math.abs(carryChain.ns - m.pathNs(carryChain.cells)) < 1e-9)
    // Its steps (what FmaxPath prints): one per net bit from the launch on, arrivals rising, the last plus setup the total.
    assert(carryChain.steps.map(_.driver) == Seq("FDRE.Q", "LUT2.O", "CARRY4.CO", "CARRY4.CO", "CARRY4.O"))
    assert(carryChain.steps.map(_.ns).sliding(2).forall(w => w(1) > w(0)))
    assert(math.abs(carryChain.steps.last.ns + m.setup - carryChain.ns) < 1e-9)
    val muxes = longest((ff("a", 2, 10) +: wideLevel("w", 10, 10)) ++ Seq(
      lut("l1", Seq(13), 14),
      ("INV", "i", Seq("I" -> Seq(14), "O" -> Seq(15))),
      carry("k", "0", Seq(15, "1", "1", "1"), o = 16 +: spare(3)),
      ff("b", 16, 17)
    ): _*)
    assert(muxes.cells == Seq("LUT1", "MUXF7", "MUXF8", "LUT1", "INV", "CARRY4"))
    assert(math.abs(muxes.ns - m.pathNs(muxes.cells)) < 1e-9)
  }

  it should "route a MUXF7's select and a carry's CI from anything but the previous slice's CO[3]" in {
    val sel = longest(ff("a", 2, 10), lut("l", Seq(10), 11), mux("MUXF7", "f7", 10, 10, 11, 12), ff("b", 12, 13))
    assert(math.abs(sel.ns - (m.tcko + m.setup + 2 * m.net + m.lut + m.muxf7)) < 1e-9)
    val ci = longest(
      ff("a", 2, 10),
      lut("l", Seq(10), 11),
      carry("k0", "0", Seq(11, "1", "1", "1"), co = Seq(spare(1)(0), 12) ++ spare(2)),
      carry("k1", 12, Seq("1", "1", "1", "1"), o = 14 +: spare(3)),
      ff("b", 14, 15)
    )
    val routed = m.tcko + m.setup + 2 * m.net + m.lut + m.carryIn + m.carryBypass + m.carryOut
    assert(math.abs(ci.ns - routed) < 1e-9, "CO[1] into CI leaves the slice")
  }

  it should "read distributed RAM through its address as a LUT, and end paths at its write pins" in {
    def ram(addr: Int, we: Int, di: Int, out: Int) = (
      "RAM64M",
      "mem",
      Seq(
        "WCLK" -> Seq(1),
        "WE" -> Seq(we),
        "ADDRA" -> Seq(addr, addr, addr, addr, addr, addr),
        "ADDRD" -> Seq("0", "0", "0", "0", "0", "0"),
        "DIA" -> Seq(di),
        "DOA" -> Seq(out)
      )
    )
    val read = longest(
      ff("a", 2, 10),
      lut("l0", Seq(10), 11),
      ram(11, 10, 10, 12),
      lut("l1", Seq(12), 13),
      ff("b", 13, 14)
    )
    assert(read.cells == Seq("LUT1", "RAM64M", "LUT1"))
    assert(math.abs(read.ns - (m.tcko + m.setup + 3 * (m.net + m.lut))) < 1e-9)
    assert(FmaxEstimate.PathCells(read.cells).luts == 3, "a distributed RAM's read counts as a LUT")
    // Only the write side: a LUT into the data input is a path that ends there.
    val write = longest(ff("a", 2, 10), lut("l0", Seq(10), 11), ram(10, 10, 11, 12))
    assert(math.abs(write.ns - (m.tcko + m.setup + m.net + m.lut)) < 1e-9)
    assert(write.to == "n11 (RAM64M.DIA)")
  }

  it should "launch a block RAM's outputs at its own clock-to-out (by its output register) and capture with its setup" in {
    def bram(reg: Int) = {
      val ram = ("RAMB36E1", "bram", Seq("CLKARDCLK" -> Seq(1), "ADDRARDADDR" -> Seq(11), "DOADO" -> Seq(12)))
      val j = netlist(ff("a", 2, 10), lut("l0", Seq(10), 11), ram, lut("l1", Seq(12), 13), ff("b", 13, 14))
      j("modules")("top")("cells")("bram")("parameters") = ujson.Obj("DOA_REG" -> ("0" * 31 + reg.toString))
      TimingGraph.longest(j, "top", m)
    }
    val bare = bram(0)
    assert(bare.cells == Seq("LUT1") && bare.from == "n12 (RAMB36E1.DOADO)", bare)
    assert(math.abs(bare.ns - (m.bramTcko + m.setup + m.net + m.lut)) < 1e-9)
    // With the output register on, the read launches nearly as a flip-flop does: the path into the address is longer.
    val registered = bram(1)
    assert(registered.to == "n11 (RAMB36E1.ADDRARDADDR)", registered)
    assert(math.abs(registered.ns - (m.tcko + m.bramSetup + m.net + m.lut)) < 1e-9)
  }

  it should "cut paths at a DSP48E1, starting and ending them there" in {
    val dsp = ("DSP48E1", "mul", Seq("CLK" -> Seq(1), "A" -> Seq(11, 11), "P" -> Seq(12, 13)))
    val p = longest(ff("a", 2, 10), lut("l0", Seq(10), 11), dsp, lut("l1", Seq(13), 14), ff("b", 14, 15))
    assert(p.cells == Seq("LUT1"))
    assert(Set(p.from, p.to).exists(_.contains("DSP48E1")))
  }

  it should "list each DSP48E1 that cuts paths without its registers, and no registered one" in {
    // Cells as `netlist` builds them, with the DSP48E1's register parameters as Yosys writes them.
    def withParams(j: ujson.Value, cell: String, regs: (String, Int)*): ujson.Value = {
      j("modules")("top")("cells")(cell)("parameters") =
        ujson.Obj.from(regs.map { case (r, v) => r -> ujson.Str(v.toBinaryString.reverse.padTo(32, '0').reverse) })
      j
    }
    def dsp(a: Int, p: Int, pcout: Option[Int] = None) =
      ("DSP48E1", "mul", Seq("CLK" -> Seq(1), "A" -> Seq(a), "P" -> Seq(p)) ++ pcout.map(b => "PCOUT" -> Seq(b)))
    def flagged(regs: Seq[(String, Int)], cells: (String, String, Pins)*) =
      TimingGraph.longest(withParams(netlist(cells: _*), "mul", regs: _*), "top", m).unregisteredDsp
    val all = Seq("AREG" -> 1, "BREG" -> 1, "MREG" -> 1, "PREG" -> 1)
    // Fed from a register, P into logic: registered at both ends, nothing to say.
    val fromReg = Seq(ff("a", 2, 10), dsp(10, 12), lut("l1", Seq(12), 13), ff("b", 13, 14))
    assert(flagged(all, fromReg: _*).isEmpty)
    // No M or P register: the multiply is in the cycle of the logic after it.
    val none = flagged(Seq("AREG" -> 1, "BREG" -> 1, "MREG" -> 0, "PREG" -> 0), fromReg: _*)
    assert(none.size == 1 && none.head.contains("no M or P register"), none)
    // M register alone is fine into flip-flops, not into logic (or over the cascade).
    val mOnly = Seq("AREG" -> 1, "BREG" -> 1, "MREG" -> 1, "PREG" -> 0)
    assert(flagged(mOnly, ff("a", 2, 10), dsp(10, 12), ff("b", 12, 14)).isEmpty)
    assert(flagged(mOnly, fromReg: _*).head.contains("P into logic"))
    assert(flagged(mOnly, ff("a", 2, 10), dsp(10, 12, Some(15)), ff("b", 12, 14), lut("l", Seq(15), 16)).nonEmpty)
    // A input through a LUT with AREG off.
    val viaLut =
      flagged(all.updated(0, "AREG" -> 0), ff("a", 2, 10), lut("l0", Seq(10), 11), dsp(11, 12), ff("b", 12, 14))
    assert(viaLut.size == 1 && viaLut.head.contains("A through logic without AREG"), viaLut)
    assert(FmaxEstimate.PathCells(Seq("LUT1"), unregisteredDsp = viaLut).described.contains("not timed"))
  }

  it should "refuse a combinational loop, naming a cell on it" in {
    val e = intercept[IllegalArgumentException](longest(
      ff("a", 2, 10),
      lut("ring0", Seq(10, 12), 11),
      lut("ring1", Seq(11), 12),
      ff("b", 12, 13)
    ))
    assert(e.getMessage.contains("combinational loop"), e.getMessage)
    assert(e.getMessage.contains("ring0") || e.getMessage.contains("ring1"), e.getMessage)
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

  it should "synthesise the grid box unit whole and black-box it in the control, as it does the box lanes" in {
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
