package rtaccel.tools

/** A cell-level delay model for the xc7z045 (Zynq-7000, Kintex-7 fabric),
  * turning a register-to-register path of Yosys cells into nanoseconds. An
  * ESTIMATE: no placement, no routing, no fan-out. docs/fmax.md states the
  * sources; in short:
  *
  *  - cell delays are the Vivado 7-series slow-corner figures printed in a
  *    published post-route report of a Zynq-7000 -1 part (Tcko 0.518 on the
  *    launching FDRE, LUT 0.124..0.327 by input pin, CARRY4 S->CO 0.550,
  *    CI->CO 0.114, CI->O 0.222..0.334); DS191 lists the same parameters
  *    (Tcko, Tilo, Tbyp/Tcinco, Tas); the -2 grade is faster, so these
  *    numbers are pessimistic for it;
  *  - MUXF7/MUXF8 from the prjxray-db timings quoted in Yosys's own
  *    xilinx/cells_sim.v (MUXF7 S->O 0.296, MUXF8 0.104 + 0.192 to the
  *    slice output);
  *  - one general-interconnect hop of `net` ns before every cell that is not
  *    fed inside its slice (a LUT feeding its slice's CARRY4 or MUXF7, a
  *    MUXF7 its MUXF8, a CARRY4 the next one: 0 ns in Vivado's reports), and
  *    none into the capturing flip-flop (packed with the last cell);
  *  - block RAM (RAMB36E1, RAMB18E1) from DS189, the 7-series block RAM's
  *    switching table (Spartan-7, -1, the slowest grade it lists): clock to
  *    data out 2.46 ns without the output register, 0.89 with it; setup
  *    0.74 (data in; the address's is 0.57);
  *  - a shift-register LUT (SRL16E, SRLC32E) launches its output 1.169 ns
  *    after a flip-flop would: prjxray-db's clock-to-Q, as Yosys's
  *    xilinx/cells_sim.v quotes it, is 1.472 ns for the SRL and 0.303 for an
  *    FDRE; the difference is added to `tcko`.
  */
final case class DelayModel(
    tcko: Double,
    setup: Double,
    lut: Double,
    muxf7: Double,
    muxf8: Double,
    carryIn: Double,
    carryBypass: Double,
    carryOut: Double,
    net: Double,
    bramTcko: Double,
    bramTckoReg: Double,
    bramSetup: Double,
    srlTcko: Double,
    name: String
) {

  /** Delay of a path given as its cell types in order (flip-flops excluded):
    * clock-to-out, the cells and their incoming nets, setup. */
  def pathNs(cells: Seq[String]): Double = {
    // An inverter is absorbed by the placer into the LUT or carry input it feeds.
    val kinds = cells.filterNot(_ == "INV").map(DelayModel.kind)
    var t = tcko + setup
    var prev = "FF"
    for ((k, i) <- kinds.zipWithIndex) {
      val inSlice = (prev, k) match {
        case ("LUT", "CARRY4") | ("LUT", "MUXF7") | ("MUXF7", "MUXF8") | ("CARRY4", "CARRY4") => true
        case _                                                                                => false
      }
      if (!inSlice) t += net
      val nextCarry = i + 1 < kinds.size && kinds(i + 1) == "CARRY4"
      t += (k match {
        case "LUT"   => lut
        case "MUXF7" => muxf7
        case "MUXF8" => muxf8
        // Entering a chain costs S->CO; inside it CI->CO; the chain's last slice also CI->O.
        case "CARRY4" => (if (prev == "CARRY4") carryBypass else carryIn) + (if (nextCarry) 0.0 else carryOut)
        case _        => 0.0
      })
      prev = k
    }
    t
  }

  def mhz(ns: Double): Double = 1000.0 / ns
}

object DelayModel {

  /** Coarse kind of a Xilinx cell type on a path. A distributed RAM's read is a LUT's (its address into its data
    * output, [[TimingGraph]]). */
  def kind(cell: String): String =
    if (cell.matches("LUT[1-6]") || TimingGraph.isLutRam(cell)) "LUT"
    else if (cell == "MUXF7" || cell == "MUXF8" || cell == "CARRY4") cell
    else "other"

  /** The model `make verilog` uses (docs/fmax.md). The net hop, 0.6 ns, is
    * calibrated on the published report: its 17-level path (9 LUT, 8 CARRY4)
    * has 9 routed nets of 0.45..1.19 ns (7.53 ns: 0.84 ns each) at a loose
    * 20 ns constraint and 5.77 ns of route (0.64 ns each) once constrained
    * to 11 ns; a timing-driven place and route at 200 MHz gets about that.
    * The LUT figure is that path's mean LUT delay (0.234 ns).
    */
  val zynq7: DelayModel = DelayModel(
    tcko = 0.518,
    setup = 0.20,
    lut = 0.234,
    muxf7 = 0.296,
    muxf8 = 0.296,
    carryIn = 0.550,
    carryBypass = 0.114,
    carryOut = 0.220,
    net = 0.60,
    bramTcko = 2.46,
    bramTckoReg = 0.89,
    bramSetup = 0.74,
    srlTcko = 0.518 + (1.472 - 0.303),
    name = "Zynq-7000 (xc7z045-2; -1 cell delays, pessimistic), 0.6 ns per routed hop"
  )
}
