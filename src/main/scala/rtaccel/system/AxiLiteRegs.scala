package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{AxiLite, AxiResp}

/** The AXI4-Lite slave generated from RegisterMap. One read and one write in
  * progress at a time (AXI4-Lite needs no more). Unmapped addresses answer
  * SLVERR (reads return 0); writes to ro registers are ignored with OKAY.
  * Address bits 1..0 are ignored (word access). While `lock`, a write to a
  * lockable register is refused with SLVERR.
  *
  * Per register (index = position in RegisterMap.regs):
  *  - ro: `hw(i)` is the value read (ID and VERSION are constants here);
  *    a `_HI` register returns the copy latched when its `_LO` was read.
  *  - rw: `value(i)` holds the register, written with byte strobes.
  *  - wo: `pulse(i)` is the written data for the write's cycle, else 0.
  *  - w1c: `value(i)` holds the bits; `hw(i)` sets bits, a written 1 clears them
  *    (a set in the same cycle wins, so no event is lost).
  */
class AxiLiteRegs extends Module {
  private val regs = RegisterMap.regs
  private val n = regs.size
  val io = IO(new Bundle {
    val axi = Flipped(new AxiLite(RegisterMap.AddrBits, 32))
    val hw = Input(Vec(n, UInt(32.W)))
    val value = Output(Vec(n, UInt(32.W)))
    val pulse = Output(Vec(n, UInt(32.W)))

    /** Freezes the lockable registers (RegisterMap.Reg.lockable): their writes answer SLVERR. */
    val lock = Input(Bool())
  })

  private def word(addr: UInt): UInt = addr(RegisterMap.AddrBits - 1, 2)
  private def hits(addr: UInt): Seq[Bool] = regs.map(r => word(addr) === (r.offset >> 2).U)

  private val stateRegs: Seq[Option[UInt]] = regs.map { r =>
    r.access match {
      case Access.Rw | Access.W1c => Some(RegInit(r.reset.getOrElse(0L).U(32.W)))
      case _                      => None
    }
  }
  private val hiShadow: Map[Int, UInt] =
    regs.zipWithIndex.collect { case (r, i) if r.hiOf.isDefined => i -> RegInit(0.U(32.W)) }.toMap

  // ---- write channel: hold AW and W until both are in, then write and answer ----
  private val awValidReg = RegInit(false.B)
  private val awAddrReg = Reg(UInt(RegisterMap.AddrBits.W))
  private val wValidReg = RegInit(false.B)
  private val wDataReg = Reg(UInt(32.W))
  private val wStrbReg = Reg(UInt(4.W))
  private val bValidReg = RegInit(false.B)
  private val bRespReg = RegInit(0.U(2.W))
  io.axi.aw.ready := !awValidReg
  io.axi.w.ready := !wValidReg
  when(io.axi.aw.fire) { awValidReg := true.B; awAddrReg := io.axi.aw.bits.addr }
  when(io.axi.w.fire) { wValidReg := true.B; wDataReg := io.axi.w.bits.data; wStrbReg := io.axi.w.bits.strb }
  private val doWrite = awValidReg && wValidReg && !bValidReg
  private val wHits = hits(awAddrReg)
  private val byteMask = Cat((3 to 0 by -1).map(b => Fill(8, wStrbReg(b))))
  when(doWrite) {
    awValidReg := false.B; wValidReg := false.B; bValidReg := true.B
    val locked = io.lock && VecInit(regs.zip(wHits).collect { case (r, h) if r.lockable => h }).asUInt.orR
    bRespReg := Mux(VecInit(wHits).asUInt.orR && !locked, AxiResp.Okay.U, AxiResp.SlvErr.U)
  }
  io.axi.b.valid := bValidReg
  io.axi.b.bits := bRespReg
  when(io.axi.b.fire) { bValidReg := false.B }

  for (((r, i), hit) <- regs.zipWithIndex.zip(wHits)) {
    val wr = doWrite && hit && !(if (r.lockable) io.lock else false.B)
    io.pulse(i) := 0.U
    r.access match {
      case Access.Rw =>
        val s = stateRegs(i).get
        when(wr) { s := (s & ~byteMask) | (wDataReg & byteMask) }
      case Access.W1c =>
        val s = stateRegs(i).get
        s := Mux(wr, s & ~(wDataReg & byteMask), s) | io.hw(i)
      case Access.Wo => io.pulse(i) := Mux(wr, wDataReg & byteMask, 0.U)
      case Access.Ro =>
    }
    io.value(i) := stateRegs(i).getOrElse(0.U)
  }

  // ---- read channel ----
  // The value is taken in two steps, both from the registers as they are in the AR cycle: each 256-byte block's
  // word, picked by the address's word bits within the block (a mux on address bits, no decode), is registered;
  // R then picks the block by the registered block bits. One wide AND-OR from the address to R's data register
  // was the unit's longest path (docs/fmax.md). R still rises the cycle after AR.
  private val rValidReg = RegInit(false.B)
  private val rRespReg = RegInit(0.U(2.W))
  io.axi.ar.ready := !rValidReg
  private val rHits = hits(io.axi.ar.bits.addr)
  private val blockBits = 8
  private val blocks = 1 << (RegisterMap.AddrBits - blockBits)
  private val inBlock = (1 << blockBits) / 4
  private val readValue: Seq[UInt] = regs.zipWithIndex.map { case (r, i) =>
    r.access match {
      case Access.Ro if r.hiOf.isDefined => hiShadow(i)
      case Access.Ro                     => r.reset.map(_.U(32.W)).getOrElse(io.hw(i))
      case Access.Wo                     => 0.U(32.W)
      case _                             => stateRegs(i).get
    }
  }
  private val usedBlocks = regs.map(_.offset >> blockBits).distinct.sorted
  private val blockWordRegs = usedBlocks.map(b => b -> RegInit(0.U(32.W))).toMap
  private val rBlockReg = RegInit(0.U((RegisterMap.AddrBits - blockBits).W))
  private val arWord = io.axi.ar.bits.addr(blockBits - 1, 2)
  when(io.axi.ar.fire) {
    rValidReg := true.B
    for (b <- usedBlocks) {
      val words = Seq.tabulate(inBlock) { w =>
        val i = regs.indexWhere(_.offset == (b << blockBits) + 4 * w)
        if (i < 0) 0.U(32.W) else readValue(i)
      }
      blockWordRegs(b) := VecInit(words)(arWord)
    }
    rBlockReg := io.axi.ar.bits.addr(RegisterMap.AddrBits - 1, blockBits)
    rRespReg := Mux(VecInit(rHits).asUInt.orR, AxiResp.Okay.U, AxiResp.SlvErr.U)
    // Reading a counter's _LO latches its _HI in the same cycle: the pair is one 64-bit value.
    for ((i, sh) <- hiShadow) {
      val lo = RegisterMap.index(regs(i).hiOf.get)
      when(rHits(lo)) { sh := io.hw(i) }
    }
  }
  io.axi.r.valid := rValidReg
  // An unmapped address reads 0: its block's word is 0, or its block has no register.
  io.axi.r.bits.data := VecInit(Seq.tabulate(blocks)(b => blockWordRegs.getOrElse(b, 0.U(32.W))))(rBlockReg)
  io.axi.r.bits.resp := rRespReg
  when(io.axi.r.fire) { rValidReg := false.B }
}
