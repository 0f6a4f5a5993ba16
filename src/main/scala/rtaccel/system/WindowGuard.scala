package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.StepCount
import rtaccel.axi.{Axi4, Axi4Addr, Axi4Master, Axi4Params}

/** The DMA window: every burst that reaches m_axi lies inside
  * `[base, limit)` (a limit of 0 stands for 2^32, the top of the 32-bit
  * space). It sits between the MemoryFabric and m_axi, so it sees every
  * master of the system (ray DMA, hit DMA, scene loader, store fills, the
  * cores' node and triangle reads).
  *
  * A burst of `len + 1` full beats at `addr` is inside when
  * `base <= addr` and `addr + (len + 1) * beatBytes <= limit`: the check is on
  * the burst's whole beats, so a window whose bounds are multiples of the
  * beat (64 bytes at 512 bits) refuses exactly the records that leave it.
  *
  * A burst outside is *refused*: it is not issued. The fabric still needs its
  * answer, so the guard gives one itself:
  *  - a refused read gets `len + 1` R beats of zero data (OKAY, so the read
  *    engine's AXI error stays the memory's own), with its ID and rlast;
  *  - a refused write has its W beats taken and not forwarded, and gets one
  *    B response.
  * The invented answer waits until no real burst of that direction is
  * outstanding (so the R beats of one ID stay in order, and the B count stays
  * per burst), and meanwhile no new burst of that direction is accepted: a
  * refusal costs a drain, which only happens in a batch that is being
  * stopped (SystemCore stops the batch on `refused`).
  *
  * Timing: the check is three 32-bit carry chains (the burst's end, and the
  * two compares), too long for one cycle at the clock the datapath allows
  * (docs/fmax.md). So AR and AW each pass two register stages (full
  * throughput, two cycles of latency per burst, no combinational path from
  * m_axi's ready back to the fabric): a 2-entry slice (HeadQueue), where the
  * burst's last byte `addr + (len + 1) * beatBytes - 1` is formed as a burst
  * enters (one add: the low bits of `len * beatBytes` are zero, so the
  * `beatBytes - 1` is a concatenation, and `end <= limit` is
  * `lastByte < limit`), and a
  * decision register, where the two compares, side by side from the slice's
  * registered head, leave their verdict. What follows the verdict (the
  * handshake, the outstanding counts, the fake answers) then starts from a
  * register, not from the compares' carry chains.
  *
  * The verdict is taken against the guard's own copy of the window, so that
  * a verdict waiting in its register still holds when the burst leaves: when
  * `base` or `limit` differ from the copy, no new burst is decided, and the
  * copy takes them once neither decision register holds a burst (a few
  * cycles after a window write; the window is set before DMA runs, and locked
  * against later writes, docs/faults.md). `refused` and `refusedAddr` are
  * registered, a cycle after the refusal, so that SystemCore's refusal
  * counter starts from a register.
  *
  * W beats follow AW order (AXI4 has no write interleaving): the fate
  * (forward or drop) of each accepted AW is queued for its W beats; a W burst
  * may run ahead of its AW by one burst (the master must not wait for AWREADY
  * before WVALID, AXI4 A3.3.1), taking the fate of the AW on offer.
  */
class WindowGuard(p: Axi4Params) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(new Axi4Master(p))
    val out = new Axi4Master(p)
    val base = Input(UInt(p.addrBits.W))
    val limit = Input(UInt(p.addrBits.W))

    /** Bursts refused (a read and a write can be refused in one cycle), the cycle after the refusal; the
      * address is the read's when both are. */
    val refused = Output(UInt(2.W))
    val refusedAddr = Output(UInt(p.addrBits.W))
  })
  private val beatShift = log2Ceil(p.beatBytes)

  /** A burst in its slice, with the address of its last byte (addrBits + 1 bits, no wrap). */
  class Held extends Bundle {
    val a = new Axi4Addr(p)
    val lastByte = UInt((p.addrBits + 1).W)
  }

  /** A burst in its decision register, with its verdict. */
  class Decided extends Bundle {
    val a = new Axi4Addr(p)
    val ok = Bool()
  }

  // The window the verdicts are taken against (above). Out of reset the copy counts as stale, so no burst is decided
  // before it has taken the registers' values.
  private val baseReg = RegInit(0.U(p.addrBits.W))
  private val limitReg = RegInit(0.U(p.addrBits.W))
  private val movedReg = RegInit(true.B)
  movedReg := io.base =/= baseReg || io.limit =/= limitReg

  /** The burst's bytes lie in the window: `base <= addr` and `end <= limit`, that is `lastByte < limit`, a limit
    * of 0 standing for 2^addrBits. The two compares run side by side; the limit-0 case is decided beside them, not
    * in front of the chain.
    */
  private def inside(h: Held): Bool = {
    val top = BigInt(1) << p.addrBits
    h.a.addr >= baseReg && (h.lastByte < limitReg || (limitReg === 0.U && h.lastByte < top.U))
  }

  /** The slice and the decision register of one direction. */
  private def decide(in: DecoupledIO[Axi4Addr]): DecoupledIO[Decided] = {
    val slice = Module(new HeadQueue(new Held))
    slice.io.enq.valid := in.valid
    slice.io.enq.bits.a := in.bits
    // addr + (len + 1) * beatBytes - 1 = addr + (len * beatBytes | (beatBytes - 1)): one add, no increment of len
    // in front of it.
    slice.io.enq.bits.lastByte := in.bits.addr +& Cat(in.bits.len, ((1 << beatShift) - 1).U(beatShift.W))
    in.ready := slice.io.enq.ready
    val validReg = RegInit(false.B)
    val heldReg = Reg(new Decided)
    val out = Wire(Decoupled(new Decided))
    out.valid := validReg
    out.bits := heldReg
    // Full throughput: the register takes the next burst in the cycle its own leaves.
    slice.io.deq.ready := (!validReg || out.ready) && !movedReg
    when(out.ready) { validReg := false.B }
    when(slice.io.deq.fire) {
      validReg := true.B
      heldReg.a := slice.io.deq.bits.a
      heldReg.ok := inside(slice.io.deq.bits)
    }
    out
  }

  /** Whether no real burst is outstanding, a register kept beside their count (StepCount: the handshakes feed a
    * select, not a carry chain). At most the fabric's read slots plus fill bursts are outstanding: 16 bits never
    * wrap.
    */
  private def outstanding(name: String, issue: Bool, retire: Bool): Bool = {
    val count = new StepCount(name, 16, Seq(0))
    count.step(issue, retire)
    count.is(0)
  }

  // ---- reads ----
  private val fakeRValidReg = RegInit(false.B)
  private val fakeRIdReg = Reg(UInt(p.idBits.W))
  private val fakeRLeftReg = Reg(UInt(8.W))
  private val ar = decide(io.in.ar)
  private val arOk = ar.bits.ok
  io.out.ar.valid := ar.valid && arOk && !fakeRValidReg
  io.out.ar.bits := ar.bits.a
  ar.ready := !fakeRValidReg && (io.out.ar.ready || !arOk)
  private val arRefused = ar.fire && !arOk
  when(arRefused) { fakeRValidReg := true.B; fakeRIdReg := ar.bits.a.id; fakeRLeftReg := ar.bits.a.len }
  private val noReads = outstanding("reads", io.out.ar.fire, io.out.r.fire && io.out.r.bits.last)
  private val fakeR = fakeRValidReg && noReads
  io.in.r.valid := io.out.r.valid || fakeR
  io.in.r.bits := io.out.r.bits
  io.out.r.ready := io.in.r.ready && !fakeR
  when(fakeR) {
    io.in.r.bits.id := fakeRIdReg
    io.in.r.bits.data := 0.U
    io.in.r.bits.resp := Axi4.RespOkay.U
    io.in.r.bits.last := fakeRLeftReg === 0.U
  }
  when(fakeR && io.in.r.ready) {
    fakeRLeftReg := fakeRLeftReg - 1.U
    when(fakeRLeftReg === 0.U) { fakeRValidReg := false.B }
  }

  // ---- writes ----
  private val fakeBValidReg = RegInit(false.B)
  private val fakeBIdReg = Reg(UInt(p.idBits.W))
  // Refused W bursts taken and not yet answered: the fake B's own, and one more that ran ahead of its AW.
  private val droppedReg = RegInit(0.U(2.W))
  // Fates of accepted AWs whose W beats have not all passed. AWs lead their W
  // by at most the WriteEngine's W queue (2 records), so 4 entries never fill;
  // if they did, AW would wait (checked, not lost).
  private val fates = Module(new Queue(Bool(), 4))
  private val aheadReg = RegInit(false.B) // a W burst went before its AW
  private val aw = decide(io.in.aw)
  private val awOk = aw.bits.ok
  private val awFree = !fakeBValidReg && (aheadReg || fates.io.enq.ready)
  io.out.aw.valid := aw.valid && awOk && awFree
  io.out.aw.bits := aw.bits.a
  aw.ready := awFree && (io.out.aw.ready || !awOk)
  // The W head's fate: queued, or (running ahead) the AW in the decision register's. That AW is the oldest without
  // a fate, and W bursts come in AW order, so a W burst ahead of its AW finds it there or upstream (where it waits).
  private val wAhead = !fates.io.deq.valid && !aheadReg && aw.valid
  private val wKnown = fates.io.deq.valid || wAhead
  private val wOk = Mux(fates.io.deq.valid, fates.io.deq.bits, awOk)
  io.out.w.valid := io.in.w.valid && wKnown && wOk
  io.out.w.bits := io.in.w.bits
  io.in.w.ready := wKnown && (!wOk || io.out.w.ready)
  private val wLast = io.in.w.fire && io.in.w.bits.last
  fates.io.deq.ready := wLast && fates.io.deq.valid
  private val aheadNow = wLast && wAhead
  fates.io.enq.valid := aw.fire && !aheadReg && !aheadNow
  fates.io.enq.bits := awOk
  when(aw.fire && aheadReg) { aheadReg := false.B }.elsewhen(aheadNow && !aw.fire) { aheadReg := true.B }
  private val dropNow = wLast && !wOk
  private val awRefused = aw.fire && !awOk
  when(awRefused) { fakeBValidReg := true.B; fakeBIdReg := aw.bits.a.id }
  private val noWrites = outstanding("writes", io.out.aw.fire, io.out.b.fire)
  private val fakeB = fakeBValidReg && noWrites && (droppedReg =/= 0.U || dropNow)
  io.in.b.valid := io.out.b.valid || fakeB
  io.in.b.bits := io.out.b.bits
  io.out.b.ready := io.in.b.ready && !fakeB
  when(fakeB) { io.in.b.bits.id := fakeBIdReg; io.in.b.bits.resp := Axi4.RespOkay.U }
  private val answered = fakeB && io.in.b.ready
  when(answered) { fakeBValidReg := false.B }
  droppedReg := droppedReg + dropNow.asUInt - answered.asUInt

  io.refused := RegNext(arRefused.asUInt +& awRefused.asUInt, 0.U)
  io.refusedAddr := RegEnable(Mux(arRefused, ar.bits.a.addr, aw.bits.a.addr), arRefused || awRefused)

  // The copy takes the window only while no verdict waits, and no burst is decided while it is stale.
  when(movedReg && !ar.valid && !aw.valid) {
    baseReg := io.base
    limitReg := io.limit
  }
}
