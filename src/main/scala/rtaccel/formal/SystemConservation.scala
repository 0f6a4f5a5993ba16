package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.{HitOut, RtAccel}
import rtaccel.axi.Axi4W
import rtaccel.system.{HeadQueue, HitDma, MemoryFabric, RayDma, SystemConfig, SystemCore, WriteEngine, WriteRecord}

/** The system's ray conservation (docs/formal.md, "System level"), the
  * system's counterpart of the core's `ray_conservation`: in every cycle
  *
  *   rays fetched (the batch's rays in each ray block RayDma receives)
  *     == hit records written (the records of the W beats) + rays held, where held =
  *        RayDma (the rays of its queued blocks not yet handed out)
  *      + the core (rays taken at its port minus hits given at its port)
  *      + HitDma (the hits in its input slice and its decision stage, its pair buffer's waiting hits, and the records
  *        of the lines in its hit queue)
  *      + WriteEngine (the records of the beats in its W queue).
  *
  * A queue's records are counted at its ports (the records of the lines or beats it took, minus those it gave),
  * so a line that leaves with fewer records than it came in with breaks the sum.
  *
  * Verification only: the monitor lives in the test tree and reads the units'
  * inner signals through ports bored into the formal SystemVerilog alone
  * (Peek); the shipped design gains nothing. Which block a ray tag carries
  * and how many of the batch's rays a block holds are the monitor's own
  * bookkeeping (from RayDma's request addresses and RAY_BASE, RAY_COUNT), not
  * RayDma's, so a ray RayDma skips, duplicates or hands out past its block
  * breaks the sum the cycle it happens; so does a hit lost between the core
  * and the W channel. The core is counted at its ports: that it keeps each
  * ray it holds is the core's own `ray_conservation` (make formal).
  */
object SystemConservation {
  def apply(dut: SystemCore[_], count: UInt, rayBase: UInt, written: UInt, maxBlocks: Int): Unit = {
    val sys = dut.sys
    val rpb = sys.raysPerBlock
    val nTags = sys.rayBlockTags
    val w = log2Ceil(maxBlocks * rpb + 1) + 2
    val rayDma = Peek[RayDma](dut, "rayDma")
    val rdQ = Peek[Queue[_ <: Data]](rayDma, "q")
    val cores = Peek[Seq[RtAccel[_]]](dut, "cores")
    require(cores.size == 1, "SystemConservation: one core")
    val hitDma = Peek[HitDma](dut, "hitDma")
    val hitQ = Peek[Queue[WriteRecord]](hitDma, "q")
    val hitInQ = Peek[HeadQueue[HitOut]](hitDma, "inQ")
    val held = Peek[Vec[Bool]](hitDma, "heldRegs")
    val s2Held = Peek[Bool](hitDma, "s2ValidReg")
    val wQ = Peek[Queue[Axi4W]](Peek[WriteEngine](Peek[MemoryFabric](dut, "fabric"), "writer"), "wQ")
    def b[A <: Data](x: A): A = Peek.bore(x)
    val reqFire = b(rayDma.io.mem.req.valid) && b(rayDma.io.mem.req.ready)
    val reqAddr = b(rayDma.io.mem.req.bits.addr)
    val reqTag = b(rayDma.io.mem.req.bits.tag)
    val respValid = b(rayDma.io.mem.resp.valid) // RayDma always takes a block
    val respTag = b(rayDma.io.mem.resp.bits.tag)
    val deqValid = b(rdQ.io.deq.valid)
    val deqFire = deqValid && b(rdQ.io.deq.ready)
    val deqTag = b(rdQ.io.deq.bits.asInstanceOf[Bundle].elements("tag").asUInt)
    val sub = b(Peek[UInt](rayDma, "subReg"))
    val coreIn = b(cores.head.io.rays.valid) && b(cores.head.io.rays.ready)
    val coreOut = b(cores.head.io.hits.valid) && b(cores.head.io.hits.ready)
    // Records in a queue, counted at its ports (from bored signals: fire and the records of the entry).
    def records(enq: DecoupledIO[_ <: Data], enqN: UInt, deq: DecoupledIO[_ <: Data], deqN: UInt): UInt = {
      val inReg = RegInit(0.U(w.W))
      inReg := inReg + Mux(b(enq.valid) && b(enq.ready), enqN, 0.U) - Mux(b(deq.valid) && b(deq.ready), deqN, 0.U)
      inReg
    }
    def beatRecords(strb: UInt): UInt = PopCount((0 until strb.getWidth / SystemConfig.HitBytes).map(g =>
      strb(SystemConfig.HitBytes * (g + 1) - 1, SystemConfig.HitBytes * g).orR
    ))
    val inHitDma =
      PopCount(held.map(x => b(x))) +& b(s2Held).asUInt +& records(hitInQ.io.enq, 1.U, hitInQ.io.deq, 1.U) +&
        records(hitQ.io.enq, PopCount(b(hitQ.io.enq.bits.halves)), hitQ.io.deq, PopCount(b(hitQ.io.deq.bits.halves)))
    val inWriter =
      records(wQ.io.enq, beatRecords(b(wQ.io.enq.bits.strb)), wQ.io.deq, beatRecords(b(wQ.io.deq.bits.strb)))

    // The batch's rays in block k (0 when the block is past RAY_COUNT or unknown: k = maxBlocks).
    def present(k: UInt): UInt = MuxLookup(k, 0.U(w.W))((0 until maxBlocks).map { j =>
      j.U -> Mux(count > (j * rpb).U, Mux(count - (j * rpb).U >= rpb.U, rpb.U, count - (j * rpb).U), 0.U).pad(w)
    })
    val kBits = log2Ceil(maxBlocks + 1)
    val blockOfTagReg = Reg(Vec(nTags, UInt(kBits.W)))
    val queuedReg = RegInit(VecInit(Seq.fill(nTags)(false.B)))
    when(reqFire) {
      blockOfTagReg(reqTag) := PriorityMux((0 until maxBlocks).map(j =>
        (reqAddr === rayBase + (j * sys.rayBlockBytes).U) -> j.U(kBits.W)
      ) :+
        (true.B -> maxBlocks.U(kBits.W)))
    }
    when(deqFire) { queuedReg(deqTag) := false.B }
    when(respValid) { queuedReg(respTag) := true.B }
    val fetchedReg = RegInit(0.U(w.W))
    val writtenReg = RegInit(0.U(w.W))
    val coreHeldReg = RegInit(0.U(w.W))
    when(respValid) { fetchedReg := fetchedReg + present(blockOfTagReg(respTag)) }
    writtenReg := writtenReg + written
    coreHeldReg := coreHeldReg + coreIn.asUInt - coreOut.asUInt
    val queued = (0 until nTags).map(t => Mux(queuedReg(t), present(blockOfTagReg(t)), 0.U(w.W))).reduce(_ +& _)
    // RayDma's head block has handed out `sub` of its rays: fetched + sub == written + held.
    val lhs = fetchedReg +& Mux(deqValid, sub, 0.U)
    val rhs = writtenReg +& queued +& coreHeldReg +& inHitDma +& inWriter
    assert(
      lhs === rhs,
      "system_ray_conservation: rays fetched != hits written + rays held by RayDma, the core, HitDma and WriteEngine"
    )
  }
}
