package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.mem.{MemPort, MemPortParams}

/** A memory the model checker plays: it takes a request whenever it has not
  * refused for `maxStall` cycles in a row, and answers each request, in any
  * order, 1 to `maxLatency` cycles after taking it, with free data and the
  * request's own tag. At most `maxLatency` requests are ever outstanding (one
  * is taken per cycle, and the oldest is at most `maxLatency` old), so
  * `maxLatency + 1` slots never fill. The rules are assumptions; that the
  * accelerator never back-pressures an answer is an assertion.
  */
class FormalMemEnv(p: MemPortParams, maxLatency: Int, maxStall: Int) extends Module {
  require(
    maxLatency >= 1 && maxStall >= 0,
    s"FormalMemEnv: maxLatency >= 1, maxStall >= 0 (got $maxLatency, $maxStall)"
  )
  private val slots = maxLatency + 1
  val io = IO(new Bundle {
    val mem = Flipped(new MemPort(p))

    /** The address of the request being answered, for assumptions on the data. */
    val respAddr = Output(UInt(p.addrBits.W))
  })

  private val busyReg = RegInit(VecInit(Seq.fill(slots)(false.B)))
  private val tagReg = Reg(Vec(slots, UInt(p.tagBits.W)))
  private val addrReg = Reg(Vec(slots, UInt(p.addrBits.W)))
  private val ageReg = Reg(Vec(slots, UInt(log2Ceil(maxLatency + 1).W)))
  private val stallReg = RegInit(0.U(log2Ceil(maxStall + 1).max(1).W))

  // ---- Requests: refused at will, but never more than maxStall cycles running ----
  private val refuse = FormalAnySeq(Bool())
  private val hasSlot = !busyReg.asUInt.andR
  io.mem.req.ready := hasSlot && (if (maxStall == 0) true.B else !refuse || stallReg === maxStall.U)
  assert(hasSlot, "mem_env_slots: more requests outstanding than the latency bound allows")
  when(io.mem.req.valid && !io.mem.req.ready) { stallReg := stallReg + 1.U }.otherwise { stallReg := 0.U }

  // ---- Answers: any outstanding request, data free, the oldest by its deadline ----
  private val respond = FormalAnySeq(Bool())
  private val choice = FormalAnySeq(UInt(log2Ceil(slots).W))
  private val chosen = respond && choice < slots.U && busyReg(choice)
  io.mem.resp.valid := chosen
  io.mem.resp.bits.tag := tagReg(choice)
  io.mem.resp.bits.data := FormalAnySeq(UInt(p.dataBits.W))
  io.respAddr := addrReg(choice)
  assert(!io.mem.resp.valid || io.mem.resp.ready, "mem_resp_ready: the accelerator back-pressured a memory answer")
  for (i <- 0 until slots) {
    assume(
      !(busyReg(i) && ageReg(i) === (maxLatency - 1).U) || (chosen && choice === i.U),
      s"mem_env_deadline: slot $i answers by its latency bound"
    )
    when(busyReg(i)) { ageReg(i) := ageReg(i) + 1.U }
  }
  when(io.mem.resp.fire) { busyReg(choice) := false.B }

  private val free = PriorityEncoder(busyReg.map(!_))
  when(io.mem.req.fire) {
    busyReg(free) := true.B
    tagReg(free) := io.mem.req.bits.tag
    addrReg(free) := io.mem.req.bits.addr
    ageReg(free) := 0.U
  }
}
