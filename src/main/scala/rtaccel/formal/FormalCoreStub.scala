package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayIn
import rtaccel.leaf.LeafIntersect
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.traversal.PrepFetch
import rtaccel.{AccelConfig, HitOut, PerfCounters}

/** The abstract core that stands in for RtAccel in the system proofs: the
  * core's own properties (exactly once, no overflow, ray conservation) are
  * checked on RtAccel itself (FormalTop); here only its promise at the ports
  * is kept. `numRayIds` slots: a ray is taken when a slot is free; it reads
  * a node record, a triangle record, both or neither (free; free addresses,
  * tag = slot), answers in any order; then its hit (the ray's number, every other field
  * free) is offered until taken. It may refuse a memory answer at most
  * `stall` cycles in a row. Asserted: each answer comes for a read that
  * waits (`core_read_answer_once`).
  *
  * Module name and ports are RtAccel's, so Yosys reads it over the real core
  * (`read_verilog -overwrite`); it instantiates nothing but FormalAnySeq.
  */
class FormalCoreStub(cfg: AccelConfig, name: String, stall: Int) extends Module {
  override def desiredName = name
  // RtAccel's node port: PrepFetch's and the traversal's requests share it, one tag bit says whose (TaggedPortArbiter.shared).
  private val nodePort: MemPortParams = PrepFetch.port(cfg).copy(tagBits = PrepFetch.port(cfg).tagBits + 1)
  val io = IO(new Bundle {
    val rays = Flipped(Decoupled(new RayIn))
    val hits = Decoupled(new HitOut(cfg))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val triBase = Input(UInt(cfg.addrBits.W))
    val nodeMem = new MemPort(nodePort)
    val triMem = new MemPort(LeafIntersect.port(cfg))
    val perf = Output(new PerfCounters)
    val broken = Output(Bool())
  })
  private val n = cfg.numRayIds
  private val busyReg = RegInit(VecInit(Seq.fill(n)(false.B)))
  private val numberReg = Reg(Vec(n, UInt(32.W)))
  // Per port and slot: the read still to issue, the read waiting for its answer.
  private val issueRegs = Seq.fill(2)(RegInit(VecInit(Seq.fill(n)(false.B))))
  private val waitRegs = Seq.fill(2)(RegInit(VecInit(Seq.fill(n)(false.B))))
  private val ports = Seq(io.nodeMem, io.triMem)

  private val free = PriorityEncoder(busyReg.map(!_))
  io.rays.ready := !busyReg.asUInt.andR
  for (((port, issue), wait) <- ports.zip(issueRegs).zip(waitRegs)) {
    val who = PriorityEncoder(issue)
    port.req.valid := issue.asUInt.orR
    port.req.bits.addr := FormalAnySeq(UInt(port.p.addrBits.W))
    port.req.bits.tag := who
    when(port.req.fire) { issue(who) := false.B; wait(who) := true.B }
    val stallReg = RegInit(0.U(log2Ceil(stall + 1).max(1).W))
    port.resp.ready := (if (stall == 0) true.B else !FormalAnySeq(Bool()) || stallReg === stall.U)
    when(port.resp.valid && !port.resp.ready) { stallReg := stallReg + 1.U }.otherwise { stallReg := 0.U }
    val t = port.resp.bits.tag
    assert(
      !port.resp.fire || (t < n.U && wait(t(log2Ceil(n) - 1, 0))),
      "core_read_answer_once: a memory answer for no waiting read"
    )
    when(port.resp.fire) { wait(t(log2Ceil(n) - 1, 0)) := false.B }
    when(io.rays.fire) { issue(free) := FormalAnySeq(Bool()) }
  }
  when(io.rays.fire) { busyReg(free) := true.B; numberReg(free) := io.rays.bits.number }

  private val doneVec = VecInit((0 until n).map(i => busyReg(i) && (issueRegs ++ waitRegs).map(!_(i)).reduce(_ && _)))
  private val out = PriorityEncoder(doneVec)
  io.hits.valid := doneVec.asUInt.orR
  io.hits.bits := FormalAnySeq(new HitOut(cfg))
  io.hits.bits.number := numberReg(out)
  when(io.hits.fire) { busyReg(out) := false.B }

  io.perf := 0.U.asTypeOf(new PerfCounters)
  io.broken := false.B
}
