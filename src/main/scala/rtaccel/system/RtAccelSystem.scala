package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.Datapath
import rtaccel.datapath.{BoxRounding, FloatDatapath, TriangleTest}

import scala.collection.immutable.SeqMap

/** Individually named ports (FlatIO keeps the names as they are): (name, width (0: Bool), driven by the module). */
final class NamedPorts(specs: Seq[(String, Int, Boolean)]) extends Record {
  val elements: SeqMap[String, Data] = SeqMap(specs.map { case (n, w, out) =>
    val t: Data = if (w == 0) Bool() else UInt(w.W)
    n -> (if (out) Output(t) else Input(t))
  }: _*)
}

/** The ZC706 system top, Verilog module `rtaccel_system`: Vivado's port names
  * (`aclk`, `aresetn` active-low synchronous, `m_axi_*` AXI4 master, `s_axi_*`
  * AXI4-Lite slave, `interrupt` level-high) around SystemCore.
  */
class RtAccelSystem[T <: Data](sys: SystemConfig, dp: Datapath[T]) extends RawModule {
  override def desiredName = "rtaccel_system"
  val aclk = IO(Input(Clock()))
  val aresetn = IO(Input(Bool()))
  val core = withClockAndReset(aclk, !aresetn)(Module(new SystemCore(sys, dp)))

  private val m = core.io.axi
  private val s = core.io.ctl
  // (name, signal, the system drives it)
  private val signals: Seq[(String, Data, Boolean)] = {
    def addr(p: String, c: DecoupledIO[rtaccel.axi.Axi4Addr]) = Seq(
      s"${p}id" -> c.bits.id,
      s"${p}addr" -> c.bits.addr,
      s"${p}len" -> c.bits.len,
      s"${p}size" -> c.bits.size,
      s"${p}burst" -> c.bits.burst,
      s"${p}lock" -> c.bits.lock,
      s"${p}cache" -> c.bits.cache,
      s"${p}prot" -> c.bits.prot,
      s"${p}qos" -> c.bits.qos,
      s"${p}valid" -> c.valid
    ).map { case (n, d) => (s"m_axi_$n", d, true) } :+ (s"m_axi_${p}ready", c.ready, false)
    addr("aw", m.aw) ++ Seq(
      ("m_axi_wdata", m.w.bits.data, true),
      ("m_axi_wstrb", m.w.bits.strb, true),
      ("m_axi_wlast", m.w.bits.last, true),
      ("m_axi_wvalid", m.w.valid, true),
      ("m_axi_wready", m.w.ready, false),
      ("m_axi_bid", m.b.bits.id, false),
      ("m_axi_bresp", m.b.bits.resp, false),
      ("m_axi_bvalid", m.b.valid, false),
      ("m_axi_bready", m.b.ready, true)
    ) ++ addr("ar", m.ar) ++ Seq(
      ("m_axi_rid", m.r.bits.id, false),
      ("m_axi_rdata", m.r.bits.data, false),
      ("m_axi_rresp", m.r.bits.resp, false),
      ("m_axi_rlast", m.r.bits.last, false),
      ("m_axi_rvalid", m.r.valid, false),
      ("m_axi_rready", m.r.ready, true),
      ("s_axi_awaddr", s.aw.bits.addr, false),
      ("s_axi_awprot", s.aw.bits.prot, false),
      ("s_axi_awvalid", s.aw.valid, false),
      ("s_axi_awready", s.aw.ready, true),
      ("s_axi_wdata", s.w.bits.data, false),
      ("s_axi_wstrb", s.w.bits.strb, false),
      ("s_axi_wvalid", s.w.valid, false),
      ("s_axi_wready", s.w.ready, true),
      ("s_axi_bresp", s.b.bits, true),
      ("s_axi_bvalid", s.b.valid, true),
      ("s_axi_bready", s.b.ready, false),
      ("s_axi_araddr", s.ar.bits.addr, false),
      ("s_axi_arprot", s.ar.bits.prot, false),
      ("s_axi_arvalid", s.ar.valid, false),
      ("s_axi_arready", s.ar.ready, true),
      ("s_axi_rdata", s.r.bits.data, true),
      ("s_axi_rresp", s.r.bits.resp, true),
      ("s_axi_rvalid", s.r.valid, true),
      ("s_axi_rready", s.r.ready, false),
      ("interrupt", core.io.interrupt, true)
    )
  }
  val ports = FlatIO(new NamedPorts(signals.map { case (n, d, out) =>
    (n, d match { case _: Bool => 0; case u => u.getWidth }, out)
  }))
  for ((n, d, out) <- signals) {
    if (out) ports.elements(n) := d else d := ports.elements(n)
  }
}

object RtAccelSystem {

  /** The system's default arithmetic: `make verilog`'s (FP of the config, watertight, conservative boxes). */
  def default(sys: SystemConfig): RtAccelSystem[_] =
    new RtAccelSystem(sys, FloatDatapath.of(sys.core, TriangleTest.Watertight, BoxRounding.Conservative))
}
