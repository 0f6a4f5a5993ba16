package rtaccel.formal

import rtaccel.system.MemoryFabric

/** The cycles from START (its B response to the host) to DONE for a batch of
  * `rays` rays, derived term by term from the configuration and the
  * environment (docs/formal.md, "System level"), never chosen. Loose where
  * the units overlap: every ray's trip is counted one after the other.
  */
object SystemBound {
  def apply(c: SystemCase, rays: Int): Seq[ResponseBound.Term] = {
    val e = c.env
    val s = e.stall
    val blocks = (rays + c.sys.raysPerBlock - 1) / c.sys.raysPerBlock
    // A record read: client arbiter 1, the fabric's request slice 1 (with the grant register, 2, with more than
    // MemoryFabric.DirectGrantClients clients: SystemCore's are each core's node and triangle ports, the scene
    // loader and RayDma), ReadEngine slot register 1, AR register 1,
    // AR queue 1, WindowGuard's AR slice and decision register 2, slave refusals s + 1;
    // the burst is overdue after L cycles, then waits at most for every beat of the bursts the slave holds
    // (3 beats each at most: a ray block); R stage 1, bank write 1, completion queue 1, head queue 1, grant 1,
    // read 1, output queue 1; the client refuses the answer at most s cycles.
    val clients = 2 * c.sys.cores + 2
    val read = 6 + MemoryFabric.requestStages(clients) + (s + 1) + e.readLatency + 3 * e.bursts + 7 + s
    Seq(
      ResponseBound.Term("start (CTRL write to the ray DMA's first request)", 2),
      // Each block: its read; the block queue and unpack 1.
      ResponseBound.Term(s"ray blocks ($blocks)", blocks * (read + 1)),
      // Each ray, one after the other: hand-over 1, the core stub's two reads through one arbiter (+1), hit offer 1;
      // HitDma's input slice 1, decision stage 1, arbiter and queue 2, WriteEngine queues 1, WindowGuard's AW slice
      // and decision register 2, AW and W refusals s + 1, the slave's B after at most bLatency refusals + 1.
      ResponseBound.Term(s"rays ($rays)", rays * (1 + read + 1 + 1 + 1 + 1 + 2 + 1 + 2 + (s + 1) + e.bLatency + 1)),
      // A hit waiting in HitDma's pair buffer for its neighbour leaves with it (the neighbour's trip, above) or, once
      // the batch's last hit is taken (HitDma's all-taken register 1, the scan's read register 1, the flush's first
      // read 1), alone as the flush's scan (a slot a cycle) reaches it: one line per slot, each through the flush's
      // stage 1, the hit queue 1, WriteEngine queues 1, WindowGuard's AW slice and decision register 2, AW and W
      // refusals s + 1 and the slave's B after at most bLatency refusals + 1.
      ResponseBound.Term(
        s"pair buffer flush (${c.sys.pairSlots} slots)",
        3 + c.sys.pairSlots * (5 + (s + 1) + e.bLatency + 1)
      ),
      // writesDone reaches RAY_COUNT: WriteEngine's count register 1, SystemCore's records-written register 1,
      // its all-written register 1, finish 1, IRQ_STATUS 1, the interrupt register 1.
      ResponseBound.Term("done", 6)
    )
  }
}
