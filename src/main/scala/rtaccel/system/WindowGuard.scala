package rtaccel.system

import chisel3._
import chisel3.util._
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
  * (docs/fmax.md). So AR and AW each pass a 2-entry register slice (full
  * throughput, one cycle of latency per burst, no combinational path from
  * m_axi's ready back to the fabric): the end `addr + (len + 1) * beatBytes`
  * is formed as a burst enters its slice, and the two compares, side by side,
  * at the slice's head, against the window registers as they are in that
  * cycle. `refused` and `refusedAddr` are registered, a cycle after the
  * refusal, so that SystemCore's refusal counter starts from a register.
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

  /** A burst in its slice, with its end address (one past its last byte; addrBits + 1 bits, no wrap). */
  class Held extends Bundle {
    val a = new Axi4Addr(p)
    val end = UInt((p.addrBits + 1).W)
  }
  private def slice(in: DecoupledIO[Axi4Addr]): DecoupledIO[Held] = {
    val held = Wire(Decoupled(new Held))
    held.valid := in.valid
    held.bits.a := in.bits
    held.bits.end := in.bits.addr +& ((in.bits.len +& 1.U) << beatShift)
    in.ready := held.ready
    // Two entries, neither pipe nor flow: full throughput with registered outputs on both sides.
    Queue(held, 2)
  }

  /** The burst's bytes lie in the window: `base <= addr` and `end <= limit`, a limit of 0 standing for 2^addrBits.
    * The two compares run side by side; the limit-0 case is decided beside them, not in front of the chain.
    */
  private def inside(h: Held): Bool = {
    val top = BigInt(1) << p.addrBits
    h.a.addr >= io.base && (h.end <= io.limit || (io.limit === 0.U && h.end <= top.U))
  }
  // Outstanding real bursts: at most the fabric's read slots plus fill bursts; 16 bits never wrap.
  // None outstanding: the count and a burst issued in the cycle before, both registers. A burst is counted from
  // registers, a cycle after it is issued (its response comes a cycle after at the earliest, so the count never
  // goes below zero), its handshake and its window check each registered alone: counted in its own cycle, the
  // window compare ran through the burst's valid into the count's add (4.94 ns in SystemCore's row, docs/fmax.md).
  private def noneOutstanding(handshake: Bool, ok: Bool, retire: Bool): Bool = {
    val issuedReg = RegNext(handshake, false.B) && RegNext(ok, false.B)
    val n = RegInit(0.U(16.W))
    n := n + issuedReg.asUInt - retire.asUInt
    n === 0.U && !issuedReg
  }

  // ---- reads ----
  private val fakeRValidReg = RegInit(false.B)
  private val fakeRIdReg = Reg(UInt(p.idBits.W))
  private val fakeRLeftReg = Reg(UInt(8.W))
  private val ar = slice(io.in.ar)
  private val arOk = inside(ar.bits)
  io.out.ar.valid := ar.valid && arOk && !fakeRValidReg
  io.out.ar.bits := ar.bits.a
  ar.ready := !fakeRValidReg && (io.out.ar.ready || !arOk)
  private val arRefused = ar.fire && !arOk
  when(arRefused) { fakeRValidReg := true.B; fakeRIdReg := ar.bits.a.id; fakeRLeftReg := ar.bits.a.len }
  // io.out.ar.fire, its handshake and its window check apart.
  private val noRealReads =
    noneOutstanding(ar.valid && !fakeRValidReg && io.out.ar.ready, arOk, io.out.r.fire && io.out.r.bits.last)
  private val fakeR = fakeRValidReg && noRealReads
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
  private val aw = slice(io.in.aw)
  private val awOk = inside(aw.bits)
  private val awFree = !fakeBValidReg && (aheadReg || fates.io.enq.ready)
  io.out.aw.valid := aw.valid && awOk && awFree
  io.out.aw.bits := aw.bits.a
  aw.ready := awFree && (io.out.aw.ready || !awOk)
  // The W head's fate: queued, or (running ahead) the AW at the slice's head's. The slice's head is the oldest
  // AW without a fate, and W bursts come in AW order, so a W burst ahead of its AW finds it there or upstream.
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
  // A dropped W burst is counted from a register, a cycle after its last beat (its fake B can go from then on):
  // counted in its own cycle, the window compare of the AW at the slice's head ran through the W side's fate into
  // the count's add and the fake B, 5.53 ns in SystemCore's row (docs/fmax.md).
  private val dropReg = RegNext(dropNow, false.B)
  private val awRefused = aw.fire && !awOk
  when(awRefused) { fakeBValidReg := true.B; fakeBIdReg := aw.bits.a.id }
  // io.out.aw.fire, its handshake and its window check apart.
  private val noRealWrites = noneOutstanding(aw.valid && awFree && io.out.aw.ready, awOk, io.out.b.fire)
  private val fakeB = fakeBValidReg && noRealWrites && (droppedReg =/= 0.U || dropReg)
  io.in.b.valid := io.out.b.valid || fakeB
  io.in.b.bits := io.out.b.bits
  io.out.b.ready := io.in.b.ready && !fakeB
  when(fakeB) { io.in.b.bits.id := fakeBIdReg; io.in.b.bits.resp := Axi4.RespOkay.U }
  private val answered = fakeB && io.in.b.ready
  when(answered) { fakeBValidReg := false.B }
  droppedReg := droppedReg + dropReg.asUInt - answered.asUInt

  io.refused := RegNext(arRefused.asUInt +& awRefused.asUInt, 0.U)
  io.refusedAddr := RegEnable(Mux(arRefused, ar.bits.a.addr, aw.bits.a.addr), arRefused || awRefused)
}
