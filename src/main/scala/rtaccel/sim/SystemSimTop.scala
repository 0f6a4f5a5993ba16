package rtaccel.sim

import chisel3._
import chisel3.util._
import rtaccel.Datapath
import rtaccel.system.{RegisterMap, SystemConfig, SystemCore}

/** Simulation wrapper of SystemCore for speed (as SimTop does for the core):
  * one packed handshake word in each direction, wide payloads peeked only
  * when valid and poked only when they change. No SystemCore output depends
  * combinationally on an input (the register block and the fabric register
  * every handshake), so a harness can peek, decide, poke, then step.
  */
class SystemSimTop[T <: Data](val sys: SystemConfig, dp: Datapath[T]) extends Module {
  val sc = Module(new SystemCore(sys, dp))
  private val m = sc.io.axi
  private val s = sc.io.ctl
  val io = IO(new Bundle {

    /** SystemSimTop.inFields, least significant first. */
    val ctrl = Input(UInt(SystemSimTop.inFields.size.W))

    /** SystemSimTop.outFields, least significant first. */
    val flags = Output(UInt(SystemSimTop.outFields.size.W))
    val ar = Output(UInt(SystemSimTop.addrBits(sys).W))
    val aw = Output(UInt(SystemSimTop.addrBits(sys).W))
    val w = Output(UInt((sys.axiDataBits + sys.axiDataBits / 8 + 1).W))

    /** data, id, resp, last (least significant first: last, resp, id, data). */
    val r = Input(UInt((sys.axiDataBits + sys.axiIdBits + 3).W))
    val b = Input(UInt((sys.axiIdBits + 2).W))
    val liteAddr = Input(UInt(RegisterMap.AddrBits.W))
    val liteWData = Input(UInt(36.W))
    val liteB = Output(UInt(2.W))
    val liteR = Output(UInt(34.W))
  })
  private def addr(a: rtaccel.axi.Axi4Addr) = Cat(a.burst, a.size, a.len, a.addr, a.id)
  io.ar := addr(m.ar.bits)
  io.aw := addr(m.aw.bits)
  io.w := Cat(m.w.bits.data, m.w.bits.strb, m.w.bits.last)
  private def in(name: String): Bool = io.ctrl(SystemSimTop.inFields.indexOf(name))
  m.ar.ready := in("arready"); m.aw.ready := in("awready"); m.w.ready := in("wready")
  m.r.valid := in("rvalid"); m.b.valid := in("bvalid")
  m.r.bits.last := io.r(0); m.r.bits.resp := io.r(2, 1); m.r.bits.id := io.r(2 + sys.axiIdBits, 3)
  m.r.bits.data := io.r >> (3 + sys.axiIdBits)
  m.b.bits.resp := io.b(1, 0); m.b.bits.id := io.b >> 2
  s.aw.valid := in("lite_awvalid"); s.w.valid := in("lite_wvalid"); s.b.ready := in("lite_bready")
  s.ar.valid := in("lite_arvalid"); s.r.ready := in("lite_rready")
  s.aw.bits.addr := io.liteAddr; s.ar.bits.addr := io.liteAddr
  s.aw.bits.prot := 0.U; s.ar.bits.prot := 0.U
  s.w.bits.data := io.liteWData(31, 0); s.w.bits.strb := io.liteWData(35, 32)
  io.liteB := s.b.bits
  io.liteR := Cat(s.r.bits.resp, s.r.bits.data)
  private val outs: Map[String, Bool] = Map(
    "arvalid" -> m.ar.valid,
    "awvalid" -> m.aw.valid,
    "wvalid" -> m.w.valid,
    "rready" -> m.r.ready,
    "bready" -> m.b.ready,
    "lite_awready" -> s.aw.ready,
    "lite_wready" -> s.w.ready,
    "lite_bvalid" -> s.b.valid,
    "lite_arready" -> s.ar.ready,
    "lite_rvalid" -> s.r.valid,
    "interrupt" -> sc.io.interrupt
  )
  io.flags := Cat(SystemSimTop.outFields.reverse.map(outs))
}

object SystemSimTop {
  val inFields: Seq[String] = Seq(
    "arready",
    "awready",
    "wready",
    "rvalid",
    "bvalid",
    "lite_awvalid",
    "lite_wvalid",
    "lite_bready",
    "lite_arvalid",
    "lite_rready"
  )
  val outFields: Seq[String] = Seq(
    "arvalid",
    "awvalid",
    "wvalid",
    "rready",
    "bready",
    "lite_awready",
    "lite_wready",
    "lite_bvalid",
    "lite_arready",
    "lite_rvalid",
    "interrupt"
  )
  def addrBits(sys: SystemConfig): Int = sys.axiIdBits + sys.axiAddrBits + 8 + 3 + 2
}
