package rtaccel.system

import chisel3._
import chisel3.util._

/** The block-RAM read ports of an on-chip store (NodeStore, TriStore) that
  * `clients` (indices into the store's `io.req`/`io.resp`) share: `ports`
  * ports of one copy of the storage. Per port, the request is registered
  * (s0), read in s0 (the BRAM's address register), and the read data put
  * into the client's output queue in s1.
  *
  * `fields` is what the store registers from a request's address (an offset
  * from its base, computed before a register so that the subtraction and the
  * block RAM's enables are not one path).
  *
  * - **One client, one port**: the port is its own. Its request goes
  *   straight into s0: response offered `NodeStore.Latency` cycles after the
  *   request, one per cycle. A request is taken on registered credit, as a
  *   sharing client is picked (below), so its ready is a register and the
  *   answer queue's count is not in front of s0.
  * - **Several clients** share the ports: each port serves whichever client
  *   is waiting, not a fixed one, so the copy's two ports serve two reads a
  *   cycle while any two of its clients ask (a client that does not ask
  *   leaves its share to the others). Each request's fields go into a
  *   two-entry queue of the client's whose head is a register (its ready is
  *   registered too, so MemoryFabric's hit test in front of it and the pick
  *   are not one path); round-robin from the client after the last one
  *   picked, port 0 takes the first head whose client has credit and port 1
  *   the second, and each selects a register into its s0: `NodeStore.SharedLatency` cycles, one more. No
  *   client is picked by two ports in a cycle, so a client starts at most one
  *   read a cycle and (both ports' latency being the same) at most one of its
  *   reads lands a cycle, in the order they were asked.
  *   Credit is registered: a client may be picked in cycle t + 1 when in
  *   cycle t its queued answers plus its reads in s0 and s1 were at most
  *   `SharedOutDepth` - 2. Between the two cycles at most one read of it
  *   starts (the pick of cycle t), none is lost and dequeues only free
  *   places, so the read picked in t + 1 finds a place among
  *   `SharedOutDepth`. The check is one register deep, which keeps the pick
  *   short; the answer queue is one entry deeper than the latency needs
  *   (`NodeStore.OutDepth`) so that a client picked every cycle still gets
  *   one answer per cycle.
  *
  * `dataStages` registers on the read data (the store's logic behind the
  * BRAM in front of the first, the rest after the last: TriStore's line
  * order, then its record's shift) delay each answer by as many cycles.
  * The answer queue is as many entries deeper and the credit counts the
  * reads in those stages too, so the queue never overflows and a client
  * picked every cycle still gets one answer per cycle.
  *
  * An enqueue that finds the answer queue full, or two reads of one client
  * landing in one cycle (neither ever expected), is reported by [[answer]],
  * the store's error.
  */
class StorePort[F <: Data](io: StoreIO, clients: Seq[Int], fields: UInt => F, ports: Int = 1, dataStages: Int = 0) {
  require(clients.nonEmpty, "StorePort: a port with no client")
  require(ports >= 1 && ports <= clients.size, s"StorePort: ${clients.size} clients cannot use $ports ports")
  require(ports == 1 || clients.size > 1, "StorePort: one client reads on one port")
  require(dataStages >= 0, s"StorePort: $dataStages data stages")
  private val n = clients.size
  private val depth = StorePort.SharedOutDepth + dataStages
  private val outQs = clients.map(c => Module(new Queue(chiselTypeOf(io.resp(c).bits), depth)))
  for ((c, j) <- clients.zipWithIndex) io.resp(c) <> outQs(j).io.deq
  private val clientBits = log2Ceil(n).max(1)
  private val tagType = chiselTypeOf(io.req(clients.head).bits.tag)

  /** Per port: a read in s0 (the BRAM reads this cycle). */
  val s0Valid: Seq[Bool] = Seq.fill(ports)(RegInit(false.B))
  private val s0ClientRegs = Seq.fill(ports)(RegInit(0.U(clientBits.W)))

  /** Per port: a read's data lands this cycle (s1). */
  val s1Valid: Seq[Bool] = s0Valid.map(v => RegNext(v, false.B))
  private val s1ClientRegs = (0 until ports).map(k => RegEnable(s0ClientRegs(k), s0Valid(k)))

  /** Per port and stage: a read's valid and client from s1 (stage 0) to its landing in the answer queue (stage
    * `dataStages`). */
  private val stageValidRegs: Seq[Seq[Bool]] =
    s1Valid.map(v => Seq.iterate(v, dataStages + 1)(RegNext(_, false.B)))
  private val stageClientRegs: Seq[Seq[UInt]] = (0 until ports).map { k =>
    (1 to dataStages).scanLeft(s1ClientRegs(k))((c, i) => RegEnable(c, stageValidRegs(k)(i - 1)))
  }

  /** `x`, entering port k's first data stage with its s1 read, carried to the last (a register per stage). */
  private def throughStages[T <: Data](k: Int, x: T): T =
    (1 to dataStages).foldLeft(x)((r, i) => RegEnable(r, stageValidRegs(k)(i - 1)))

  private def mine(valid: Bool, client: UInt, j: Int): Bool = if (n == 1) valid else valid && client === j.U
  private def inFlight(j: Int): UInt =
    (0 until ports).map(k =>
      (mine(s0Valid(k), s0ClientRegs(k), j) +: (0 to dataStages).map(i =>
        mine(stageValidRegs(k)(i), stageClientRegs(k)(i), j)
      )).map(_.asUInt).reduce(_ +& _)
    ).reduce(_ +& _)
  private def held(j: Int): UInt = outQs(j).io.count +& inFlight(j)

  // Per port: a read starts (fire), for which client (chosen), with which fields and tag.
  private val picks: Seq[(Bool, UInt, F, UInt)] =
    if (n == 1) {
      val r = io.req(clients.head)
      // Credit as a sharing client's (below), counted in a register: the answer queue's count and the reads in
      // flight, summed and compared, were the stores' longest path into s0 (docs/fmax.md).
      val heldReg = RegInit(0.U(log2Ceil(depth + 1).W))
      r.ready := RegNext(heldReg <= (depth - 2).U, false.B)
      heldReg := heldReg + r.fire.asUInt - io.resp(clients.head).fire.asUInt
      assert(heldReg === held(0), "store_port_credit: the client's count differs from its queued and read records")
      Seq((r.fire, 0.U(clientBits.W), fields(r.bits.addr), r.bits.tag))
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
      // A client's answers queued plus its reads in s0 and s1, counted in a register: reads picked less answers
      // taken. It equals `held` (a read picked in cycle t is in s0 at t + 1, in s1 at t + 2, queued from
      // t + 3 + dataStages) without the answer queue's count and the sum of the ports' reads in front of the compare: as a
      // sum it was the stores' longest path with two ports (6.00 ns).
      val heldRegs = Seq.fill(n)(RegInit(0.U(log2Ceil(depth + 1).W)))
      val creditRegs = heldRegs.map(h => RegNext(h <= (depth - 2).U, false.B))
      // Round-robin: the waiting heads (with credit) in order from the client after the last one picked; port k
      // takes the k-th. Both picks are one table of the waiting vector and the pointer, registers all (n <= 6:
      // n + log2(n) inputs, a LUT level or two), not a chain of arbiters' compares.
      val waiting = VecInit((0 until n).map(j => heads(j).valid && creditRegs(j))).asUInt
      val nextReg = RegInit(0.U(clientBits.W))
      val grants = StorePort.picks(n, ports).map(table => VecInit(table.map(_.U(n.W)))(Cat(nextReg, waiting)))
      val fires = grants.map(_.orR)
      for (j <- 0 until n) {
        val picked = grants.map(_(j)).reduce(_ || _)
        heads(j).ready := picked
        heldRegs(j) := heldRegs(j) + picked.asUInt - io.resp(clients(j)).fire.asUInt
        assert(heldRegs(j) === held(j), "store_port_credit: a client's count differs from its queued and read records")
      }
      val chosens = grants.map(g => OHToUInt(g).pad(clientBits))
      // The pointer moves past the last client picked this cycle (port k picks only if port k - 1 did).
      val last = PriorityMux(fires.reverse, chosens.reverse)
      when(fires.head) { nextReg := Mux(last === (n - 1).U, 0.U, last + 1.U) }
      grants.indices.map { k =>
        val head = VecInit(heads.map(_.bits))(chosens(k))
        (fires(k), chosens(k), head.fields, head.tag)
      }
    }
  for (((fire, chosen, _, _), k) <- picks.zipWithIndex) {
    s0Valid(k) := fire
    when(fire) { s0ClientRegs(k) := chosen }
  }

  /** Per port: the chosen request's fields and tag, registered in s0. */
  val s0Fields: Seq[F] = picks.map { case (fire, _, f, _) => RegEnable(f, fire) }
  val s0Tag: Seq[UInt] = picks.map { case (fire, _, _, t) => RegEnable(t, fire) }

  /** Per port: the s0 read's tag in s1, then down the data stages. */
  private val landTagRegs = (0 until ports).map { k =>
    throughStages(k, RegEnable(s0Tag(k), s0Valid(k)))
  }

  /** Enqueue `after(data(k))` (`data(k)`: what port k read in s0, in s1, carried through the data stages;
    * `after`: the store's logic behind the last stage) for its read's client; true if a queue was full or two
    * ports' reads of one client landed at once (neither ever expected).
    */
  def answer(data: Seq[UInt], after: UInt => UInt = d => d): Bool = {
    require(data.size == ports, s"StorePort.answer: ${data.size} ports' data for $ports ports")
    val landData = data.zipWithIndex.map { case (d, k) =>
      after(throughStages(k, d))
    }
    val errors = for (j <- 0 until n) yield {
      val q = outQs(j)
      val lands = (0 until ports).map(k => mine(stageValidRegs(k)(dataStages), stageClientRegs(k)(dataStages), j))
      q.io.enq.valid := lands.reduce(_ || _)
      q.io.enq.bits.data := (if (ports == 1) landData.head else Mux1H(lands, landData))
      q.io.enq.bits.tag := (if (ports == 1) landTagRegs.head else Mux1H(lands, landTagRegs))
      (q.io.enq.valid && !q.io.enq.ready) || (if (ports == 1) false.B else PopCount(lands) > 1.U)
    }
    errors.reduce(_ || _)
  }
}

object StorePort {

  /** A client's answer queue: [[NodeStore.OutDepth]] + 1, for the registered credit. */
  val SharedOutDepth: Int = NodeStore.OutDepth + 1

  /** A request waiting for a shared port: the store's fields of its address, and its tag. */
  class Entry[F <: Data](f: F, t: UInt) extends Bundle {
    val fields = f.cloneType
    val tag = t.cloneType
  }

  /** The round-robin picks of `ports` ports among `n` clients, as tables indexed by (pointer, waiting): entry
    * (p << n | w) of table k is the one-hot of the k-th client waiting in `w` counted from client p (0 if fewer
    * than k + 1 wait, or p >= n).
    */
  def picks(n: Int, ports: Int): Seq[Seq[Int]] = {
    require(
      n >= 2 && n <= 6,
      s"StorePort: $n clients on one copy of a store; at most 6 share its ports (raise SystemConfig.storeCopies)"
    )
    val pointers = 1 << log2Ceil(n)
    (0 until ports).map { k =>
      for (p <- 0 until pointers; w <- 0 until (1 << n))
        yield
          if (p >= n) 0
          else (0 until n).map(i => (p + i) % n).filter(j => (w >> j & 1) == 1).lift(k).map(1 << _).getOrElse(0)
    }
  }

  /** Clients on a copy's read ports: `ports` of copy `copy` (0: port A, which also takes the fill's writes; 1:
    * port B) serve `clients`.
    */
  final case class Group(copy: Int, ports: Seq[Int], clients: Seq[Int])

  /** The groups when `clients` share `copies` dual-ported copies: with at most two clients per copy, client c has
    * port c mod 2 of copy c / 2 to itself; with more, the clients c of copy c mod copies share both its ports.
    */
  def assign(clients: Int, copies: Int): Seq[Group] =
    if (clients <= 2 * copies) (0 until clients).map(c => Group(c / 2, Seq(c % 2), Seq(c)))
    else (0 until copies).map(k => Group(k, Seq(0, 1), (k until clients by copies).toSeq))
}
