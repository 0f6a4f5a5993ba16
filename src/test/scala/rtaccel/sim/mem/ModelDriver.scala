package rtaccel.sim.mem

import scala.collection.mutable

/** Drives memory-system models like a DUT would, for the model's own specs:
  * each port issues its next address as soon as it is accepted and takes
  * every response at once. All ports issue before any ticks, as in the
  * accelerator harness, so a shared DRAM sees a whole cycle's requests.
  */
object ModelDriver {

  /** A response: (cycle it was seen, tag = index of its request, data). */
  type Response = (Long, Int, BigInt)

  /** Port `i` issues `addrs(i)(k)` no earlier than cycle `from(i)(k)`
    * (default: as soon as accepted). Returns each port's responses.
    */
  def drivePorts(
      ms: Seq[MemorySystemModel],
      addrs: Seq[Seq[Long]],
      from: Seq[Seq[Long]] = Nil,
      maxCycles: Int = 100000
  ): Seq[Seq[Response]] = {
    val out = ms.map(_ => mutable.ArrayBuffer.empty[Response])
    val next = Array.fill(ms.size)(0)
    def pending(i: Int) = next(i) < addrs(i).size
    while ((ms.indices.exists(pending) || !ms.forall(_.idle)) && ms.head.cycles < maxCycles) {
      for ((m, i) <- ms.zipWithIndex) {
        val due = pending(i) && from.lift(i).forall(f => f(next(i)) <= m.cycles)
        if (due) {
          if (m.reqReady(addrs(i)(next(i)))) { m.accept(addrs(i)(next(i)), next(i)); next(i) += 1 }
          else m.stalled()
        }
        m.response.foreach { case (tag, data) => out(i) += ((m.cycles, tag, data)); m.responseTaken() }
      }
      ms.foreach(_.tick())
    }
    assert(!ms.indices.exists(pending) && ms.forall(_.idle), s"models did not drain within $maxCycles cycles")
    out.map(_.toSeq)
  }

  def drive(m: MemorySystemModel, addrs: Seq[Long], maxCycles: Int = 100000): Seq[Response] =
    drivePorts(Seq(m), Seq(addrs), maxCycles = maxCycles).head
}
