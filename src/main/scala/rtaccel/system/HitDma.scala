package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.{ErrorFlags, HitOut}

/** Collects the cores' hits (round-robin) and writes each as the 32-byte hit
  * record at HIT_BASE + 32 * number (docs/reports/register-map.md). Counts the batch's
  * rays per error flag. A hit whose number is not in the batch is not written
  * and sets `broken` (never expected: the ray DMA numbers rays 0..count-1).
  */
class HitDma(sys: SystemConfig) extends Module {
  val io = IO(new Bundle {
    val start = Input(Bool())
    val hitBase = Input(UInt(sys.axiAddrBits.W))
    val rayCount = Input(UInt(32.W))
    val hits = Vec(sys.cores, Flipped(Decoupled(new HitOut(sys.core))))
    val write = Decoupled(new WriteRecord(sys))
    val errCount = Output(Vec(ErrorFlags.width, UInt(32.W)))
    val broken = Output(Bool())
  })
  private val arb = Module(new RRArbiter(new HitOut(sys.core), sys.cores))
  arb.io.in <> io.hits
  private val baseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val countReg = RegInit(0.U(32.W))
  private val errReg = RegInit(VecInit(Seq.fill(ErrorFlags.width)(0.U(32.W))))
  private val brokenReg = RegInit(false.B)
  when(io.start) { baseReg := io.hitBase; countReg := io.rayCount; errReg.foreach(_ := 0.U) }

  private val h = arb.io.out.bits
  private val inBatch = h.number < countReg
  private val q = Module(new Queue(new WriteRecord(sys), sys.hitQueue))
  q.io.enq.valid := arb.io.out.valid && inBatch
  arb.io.out.ready := q.io.enq.ready || !inBatch
  q.io.enq.bits.addr := baseReg + (h.number << log2Ceil(SystemConfig.HitBytes))
  q.io.enq.bits.data := HitDma.record(h)
  when(arb.io.out.fire) {
    when(!inBatch) { brokenReg := true.B }
    assert(inBatch, "hit_in_batch: a hit whose number is not in the batch")
    for (k <- 0 until ErrorFlags.width) when(inBatch && h.errors(k)) { errReg(k) := errReg(k) + 1.U }
  }
  io.write <> q.io.deq
  io.errCount := errReg
  io.broken := brokenReg
}

object HitDma {

  /** The 32-byte record, little-endian: number, status (bit 0 hit, bits 8.. errors), t, u, v, prim, 0, 0. */
  def record(h: HitOut): UInt = {
    val status = Cat(h.errors, 0.U(7.W), h.hit)
    Cat(0.U(64.W), h.prim.pad(32), h.v, h.u, h.t, status.pad(32), h.number)
  }
  val StatusErrorShift = 8
}
