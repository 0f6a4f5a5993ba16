package rtaccel.system

import chisel3._
import chisel3.util._

/** One block-RAM read port of an on-chip store (NodeStore, TriStore), for
  * `clients` (indices into the store's `io.req`/`io.resp`). The request is
  * registered (s0), read in s0 (the BRAM's address register), and the read
  * data put into the client's output queue in s1.
  *
  * `fields` is what the store registers from a request's address (an offset
  * from its base, computed before a register so that the subtraction and the
  * block RAM's enables are not one path).
  *
  * - **One client**: the port is its own. Its request goes straight into s0:
  *   response offered `NodeStore.Latency` cycles after the request, one per
  *   cycle. A request is taken while the client's queued answers plus its
  *   reads in s0 and s1 are fewer than `NodeStore.OutDepth`, so every read
  *   has a place when it lands.
  * - **Several clients** share it round-robin. Each request's fields go into
  *   a two-entry queue of the client's whose head is a register (its ready is
  *   registered too, so MemoryFabric's hit test in front of it and the pick
  *   are not one path); the pick, among heads whose clients have credit,
  *   selects a register into s0: `NodeStore.SharedLatency` cycles, one more.
  *   Credit is registered: a client may be picked in cycle t + 1 when in
  *   cycle t its queued answers plus its reads in s0 and s1 were at most
  *   `SharedOutDepth` - 2. Between the two cycles at most one read of it
  *   starts (the pick of cycle t), none is lost and dequeues only free
  *   places, so the read picked in t + 1 finds a place among
  *   `SharedOutDepth`. The check is one register deep, which keeps the pick
  *   short; the answer queue is one entry deeper than a port of one client's
  *   so that a client alone on a shared port still gets one answer per cycle.
  *
  * An enqueue that finds the answer queue full (never expected) is reported
  * by [[answer]], the store's error.
  */
class StorePort[F <: Data](io: StoreIO, clients: Seq[Int], fields: UInt => F) {
  require(clients.nonEmpty, "StorePort: a port with no client")
  private val n = clients.size
  private val depth = if (n == 1) NodeStore.OutDepth else StorePort.SharedOutDepth
  private val outQs = clients.map(c => Module(new Queue(chiselTypeOf(io.resp(c).bits), depth)))
  for ((c, j) <- clients.zipWithIndex) io.resp(c) <> outQs(j).io.deq
  private val clientBits = log2Ceil(n).max(1)
  private val tagType = chiselTypeOf(io.req(clients.head).bits.tag)

  /** A read in s0 (the BRAM reads this cycle). */
  val s0Valid: Bool = RegInit(false.B)
  private val s0ClientReg = RegInit(0.U(clientBits.W))

  /** A read's data lands this cycle (s1). */
  val s1Valid: Bool = RegInit(false.B)
  private val s1ClientReg = RegEnable(s0ClientReg, s0Valid)
  s1Valid := s0Valid

  private def inFlight(j: Int): UInt =
    if (n == 1) s0Valid.asUInt +& s1Valid.asUInt
    else (s0Valid && s0ClientReg === j.U).asUInt +& (s1Valid && s1ClientReg === j.U).asUInt
  private def held(j: Int): UInt = outQs(j).io.count +& inFlight(j)

  private val fire = Wire(Bool())
  private val chosen = Wire(UInt(clientBits.W))
  private val (nextFields, nextTag) =
    if (n == 1) {
      val r = io.req(clients.head)
      r.ready := held(0) < depth.U
      fire := r.fire
      chosen := 0.U
      (fields(r.bits.addr), r.bits.tag)
    } else {
      val heads = clients.map { c =>
        val f = fields(io.req(c).bits.addr)
        val q = Module(new HeadQueue(new StorePort.Entry(chiselTypeOf(f), tagType)))
        q.io.enq.valid := io.req(c).valid
        q.io.enq.bits.fields := f
        q.io.enq.bits.tag := io.req(c).bits.tag
        io.req(c).ready := q.io.enq.ready
        q.io.deq
      }
      val creditRegs = (0 until n).map(j => RegNext(held(j) <= (depth - 2).U, false.B))
      val arb = Module(new RRArbiter(UInt(0.W), n))
      for (j <- 0 until n) {
        arb.io.in(j).valid := heads(j).valid && creditRegs(j)
        arb.io.in(j).bits := DontCare
        heads(j).ready := arb.io.in(j).ready && creditRegs(j)
      }
      arb.io.out.ready := true.B
      fire := arb.io.out.fire
      chosen := arb.io.chosen
      val head = VecInit(heads.map(_.bits))(chosen)
      (head.fields, head.tag)
    }
  s0Valid := fire
  when(fire) { s0ClientReg := chosen }

  /** The chosen request's fields and tag, registered in s0. */
  val s0Fields: F = RegEnable(nextFields, fire)
  val s0Tag: UInt = RegEnable(nextTag, fire)

  /** The s0 read's tag in s1. */
  val s1Tag: UInt = RegEnable(s0Tag, s0Valid)

  /** Enqueue `data` (the record read in s0) for the s1 read's client; true if its queue was full (never expected). */
  def answer(data: UInt): Bool = {
    for (j <- 0 until n) {
      val q = outQs(j)
      q.io.enq.valid := s1Valid && (if (n == 1) true.B else s1ClientReg === j.U)
      q.io.enq.bits.data := data
      q.io.enq.bits.tag := s1Tag
    }
    outQs.map(q => q.io.enq.valid && !q.io.enq.ready).reduce(_ || _)
  }
}

object StorePort {

  /** A shared port's answer queue per client: [[NodeStore.OutDepth]] + 1, for the registered credit. */
  val SharedOutDepth: Int = NodeStore.OutDepth + 1

  /** A request waiting for a shared port: the store's fields of its address, and its tag. */
  class Entry[F <: Data](f: F, t: UInt) extends Bundle {
    val fields = f.cloneType
    val tag = t.cloneType
  }

  /** The clients of each read port when `clients` share `copies` dual-ported copies: client c on port c mod ports
    * (ports 2k and 2k + 1 are copy k's two ports; the even one also takes the fill's writes). */
  def assign(clients: Int, copies: Int): Seq[Seq[Int]] = {
    val ports = (2 * copies).min(clients)
    (0 until ports).map(p => (p until clients by ports).toSeq)
  }
}

/** A two-entry queue whose head is a register (`deq.bits` is read from no
  * memory and through no mux) and whose `enq.ready` is a register: a skid
  * buffer. One entry in and one out per cycle while the head drains.
  */
class HeadQueue[T <: Data](gen: T) extends Module {
  val io = IO(new Bundle {
    val enq = Flipped(Decoupled(gen))
    val deq = Decoupled(gen)
  })
  private val headValidReg = RegInit(false.B)
  private val headReg = Reg(gen)
  private val spareValidReg = RegInit(false.B)
  private val spareReg = Reg(gen)
  io.enq.ready := !spareValidReg
  io.deq.valid := headValidReg
  io.deq.bits := headReg
  // The head is free for the next entry when empty or leaving; the spare, when full, goes first (it came first).
  when(!headValidReg || io.deq.ready) {
    headValidReg := spareValidReg || io.enq.valid
    headReg := Mux(spareValidReg, spareReg, io.enq.bits)
    spareValidReg := false.B
  }.elsewhen(io.enq.valid && !spareValidReg) {
    spareValidReg := true.B
    spareReg := io.enq.bits
  }
}
