package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4, Axi4Master, Axi4Params}

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
  * stopped (SystemCore stops the batch on `refused`). With no refusal the
  * guard adds no cycle: AR and AW pass through combinationally.
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

    /** Pulses for each refused burst (read or write), with its address. */
    val refused = Output(Bool())
    val refusedAddr = Output(UInt(p.addrBits.W))
  })
  private val beatShift = log2Ceil(p.beatBytes)
  private val limitTop = Mux(io.limit === 0.U, (BigInt(1) << p.addrBits).U, io.limit)

  /** The burst's bytes lie in the window. */
  def inside(addr: UInt, len: UInt): Bool = addr >= io.base && (addr +& ((len +& 1.U) << beatShift)) <= limitTop
  // Outstanding real bursts: at most the fabric's read slots plus fill bursts; 16 bits never wrap.
  private def outstanding(issue: Bool, retire: Bool): UInt = {
    val n = RegInit(0.U(16.W))
    n := n + issue.asUInt - retire.asUInt
    n
  }

  // ---- reads ----
  private val fakeRValidReg = RegInit(false.B)
  private val fakeRIdReg = Reg(UInt(p.idBits.W))
  private val fakeRLeftReg = Reg(UInt(8.W))
  private val arOk = inside(io.in.ar.bits.addr, io.in.ar.bits.len)
  io.out.ar.valid := io.in.ar.valid && arOk && !fakeRValidReg
  io.out.ar.bits := io.in.ar.bits
  io.in.ar.ready := !fakeRValidReg && (io.out.ar.ready || !arOk)
  private val arRefused = io.in.ar.fire && !arOk
  when(arRefused) { fakeRValidReg := true.B; fakeRIdReg := io.in.ar.bits.id; fakeRLeftReg := io.in.ar.bits.len }
  private val realReads = outstanding(io.out.ar.fire, io.out.r.fire && io.out.r.bits.last)
  private val fakeR = fakeRValidReg && realReads === 0.U
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
  private val awOk = inside(io.in.aw.bits.addr, io.in.aw.bits.len)
  private val awFree = !fakeBValidReg && (aheadReg || fates.io.enq.ready)
  io.out.aw.valid := io.in.aw.valid && awOk && awFree
  io.out.aw.bits := io.in.aw.bits
  io.in.aw.ready := awFree && (io.out.aw.ready || !awOk)
  // The W head's fate: queued, or (running ahead) the AW on offer's.
  private val wAhead = !fates.io.deq.valid && !aheadReg && io.in.aw.valid
  private val wKnown = fates.io.deq.valid || wAhead
  private val wOk = Mux(fates.io.deq.valid, fates.io.deq.bits, awOk)
  io.out.w.valid := io.in.w.valid && wKnown && wOk
  io.out.w.bits := io.in.w.bits
  io.in.w.ready := wKnown && (!wOk || io.out.w.ready)
  private val wLast = io.in.w.fire && io.in.w.bits.last
  fates.io.deq.ready := wLast && fates.io.deq.valid
  private val aheadNow = wLast && wAhead
  fates.io.enq.valid := io.in.aw.fire && !aheadReg && !aheadNow
  fates.io.enq.bits := awOk
  when(io.in.aw.fire && aheadReg) { aheadReg := false.B }.elsewhen(aheadNow && !io.in.aw.fire) { aheadReg := true.B }
  private val dropNow = wLast && !wOk
  private val awRefused = io.in.aw.fire && !awOk
  when(awRefused) { fakeBValidReg := true.B; fakeBIdReg := io.in.aw.bits.id }
  private val realWrites = outstanding(io.out.aw.fire, io.out.b.fire)
  private val fakeB = fakeBValidReg && realWrites === 0.U && (droppedReg =/= 0.U || dropNow)
  io.in.b.valid := io.out.b.valid || fakeB
  io.in.b.bits := io.out.b.bits
  io.out.b.ready := io.in.b.ready && !fakeB
  when(fakeB) { io.in.b.bits.id := fakeBIdReg; io.in.b.bits.resp := Axi4.RespOkay.U }
  private val answered = fakeB && io.in.b.ready
  when(answered) { fakeBValidReg := false.B }
  droppedReg := droppedReg + dropNow.asUInt - answered.asUInt

  io.refused := arRefused || awRefused
  io.refusedAddr := Mux(arRefused, io.in.ar.bits.addr, io.in.aw.bits.addr)
}
