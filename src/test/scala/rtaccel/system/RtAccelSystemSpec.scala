package rtaccel.system

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.tools.Synth
import rtaccel.AccelConfig
import rtaccel.bvh.BvhLayout
import rtaccel.sim.FieldDatapath

/** The top's Verilog carries exactly the contract's port names (so Vivado infers m_axi, s_axi, the clock, reset and interrupt). */
class RtAccelSystemSpec extends AnyFlatSpec {
  behavior of "rtaccel_system"

  it should "have the contract's port names and no others" in {
    val cfg = AccelConfig(
      numRayIds = 4,
      stackDepth = 8,
      maxNodes = 1 << 8,
      maxTriangles = 1 << 8,
      maxLeafSize = 4,
      layout = BvhLayout.Wide(4)
    )
    val sv = Synth.emit(new RtAccelSystem(SystemConfig(core = cfg, cores = 1), FieldDatapath))
    val header =
      sv.substring(sv.indexOf("module rtaccel_system("), sv.indexOf(");", sv.indexOf("module rtaccel_system(")))
    // firtool lists one port per line, its name last; a run of ports of one direction and width shares one `input`/`output`.
    val got = header.linesIterator.drop(1).flatMap(l => """(\w+),?\s*$""".r.findFirstMatchIn(l).map(_.group(1))).toSet
    val addr = Seq("id", "addr", "len", "size", "burst", "lock", "cache", "prot", "qos", "valid", "ready")
    val m = (addr.map("aw" + _) ++ Seq(
      "wdata",
      "wstrb",
      "wlast",
      "wvalid",
      "wready",
      "bid",
      "bresp",
      "bvalid",
      "bready"
    ) ++ addr.map("ar" + _) ++
      Seq("rid", "rdata", "rresp", "rlast", "rvalid", "rready")).map("m_axi_" + _)
    val s = Seq(
      "awaddr",
      "awprot",
      "awvalid",
      "awready",
      "wdata",
      "wstrb",
      "wvalid",
      "wready",
      "bresp",
      "bvalid",
      "bready",
      "araddr",
      "arprot",
      "arvalid",
      "arready",
      "rdata",
      "rresp",
      "rvalid",
      "rready"
    ).map("s_axi_" + _)
    val want = (m ++ s ++ Seq("aclk", "aresetn", "interrupt")).toSet
    assert(
      got == want,
      s"missing: ${(want -- got).toSeq.sorted.mkString(", ")}; extra: ${(got -- want).toSeq.sorted.mkString(", ")}"
    )
  }
}
