package rtaccel.sim

import chisel3._
import chiseltest._
import rtaccel.golden.{HitRecord, RayRecord}
import rtaccel.scene.MemoryImage
import rtaccel.sim.mem.{Backing, DramStats, MemPortDriver, MemStats, MemoryKind, MemoryParams, MemorySystemModel}

import scala.collection.mutable
import scala.util.Random

/** How the world around the accelerator behaves during a run. */
final case class Environment(
    node: MemoryParams,
    tri: MemoryParams,
    /** What holds the scene: one DRAM behind both ports (the default), or on-chip memory per port. */
    memory: MemoryKind = MemoryKind.Ddr(),
    /** Chance that the host offers no ray in a cycle. */
    rayGap: Double = 0.0,
    /** Chance that the consumer refuses a hit in a cycle. */
    hitRefuse: Double = 0.0,
    /** Chance that a memory port refuses a request on top of its own limits. */
    memRefuse: Double = 0.0,
    seed: Long = 1
)

/** What the counters said at one moment of a run: after `hits` answers, at `cycle`. */
final case class Snapshot(hits: Int, cycle: Long, perf: Map[String, BigInt], dram: Option[DramStats])

/** `dram` is the shared DRAM's account (None on chip). `window`: the counters when the run had answered
  * [[RunResult.WindowFrom]] and [[RunResult.WindowTo]] of its rays (None if the harness took none): the batch's
  * middle, away from its start, when the pipelines fill, and its end, when the last rays drain.
  */
final case class RunResult(
    hits: Seq[HitRecord],
    cycles: Long,
    perf: Map[String, BigInt],
    node: MemStats,
    tri: MemStats,
    dram: Option[DramStats],
    window: Option[(Snapshot, Snapshot)] = None
)

object RunResult {

  /** The window's ends, as shares of a run's answers. */
  val WindowFrom = 0.2
  val WindowTo = 0.8

  /** The answer counts at which a run of `rays` takes its snapshots (none for a run too short to have a middle). */
  def windowHits(rays: Int): Option[(Int, Int)] = {
    val (from, to) = ((rays * WindowFrom).ceil.toInt, (rays * WindowTo).floor.toInt)
    if (from >= 1 && to > from) Some((from, to)) else None
  }
}

/** Runs rays through an RtAccel (in its SimTop wrapper) cycle by cycle (single-threaded, no `fork`),
  * with memory models on both ports, sharing one DRAM (or each on chip). Each
  * port serves records of its own data width, so wider nodes cost what they
  * weigh. Fails loudly if a hit comes for a ray
  * not in flight, comes twice, if the design flags itself broken, or if no
  * progress is made for `stallLimit` cycles (a deadlock). `progress` gets the
  * count of rays answered every 2^12 cycles (seconds under chiseltest).
  */
object AccelHarness {
  def run[T <: Data](
      dut: SimTop[T],
      img: MemoryImage,
      rays: IndexedSeq[RayRecord],
      env: Environment,
      maxCycles: Long = 10000000L,
      stallLimit: Int = 20000,
      progress: Long => Unit = _ => ()
  ): RunResult = {
    val rnd = new Random(env.seed)
    // Each port serves whole records of its width: a node (32 B nori, 32 K B wide) or a triangle.
    val (nodeBytes, triBytes) = (dut.accel.io.nodeMem.p.dataBits / 8, dut.accel.io.triMem.p.dataBits / 8)
    require(
      nodeBytes == img.nodeBytes,
      s"${img.source}: ${img.layout.name} nodes of ${img.nodeBytes} bytes, but the hardware reads $nodeBytes-byte nodes"
    )
    val (backing, dram) = Backing.forPorts(env.memory)
    def driver(p: MemoryParams, recordBytes: Int, name: String) =
      new MemPortDriver(
        new MemorySystemModel(img, recordBytes, p, name, backing),
        env.memRefuse,
        new Random(rnd.nextLong())
      )
    val node = driver(env.node, nodeBytes, "node")
    val tri = driver(env.tri, triBytes, "triangle")
    val st = new SimTop.Status(dut.accel)
    val io = dut.io
    io.nodeBase.poke(img.nodeOffset.U)
    io.triBase.poke(img.triOffset.U)
    dut.clock.setTimeout(0)

    require(rays.map(_.number).distinct.size == rays.size, "ray numbers must be distinct")
    val inFlight = mutable.Set.empty[Long]
    val hits = mutable.ArrayBuffer.empty[HitRecord]
    // The counters at the window's ends (RunResult.window): two peeks of the performance counters per run.
    val windowAt = RunResult.windowHits(rays.size)
    val snapshots = mutable.ArrayBuffer.empty[Snapshot]
    var next = 0
    var cycle = 0L
    var lastProgress = 0L
    // What is on the inputs now: each chiseltest call costs microseconds, so
    // inputs are packed, poked only when they change, and all outputs come
    // back in one packed peek.
    var ctrlNow, rayNow, nodeRespNow, triRespNow = BigInt(-1)
    def set(word: UInt, value: BigInt, now: BigInt): BigInt = { if (value != now) word.poke(value.U); value }
    val (tagN, tagT) = (dut.accel.io.nodeMem.p.tagBits, dut.accel.io.triMem.p.tagBits)
    while (hits.size < rays.size) {
      if (cycle >= maxCycles)
        throw new AssertionError(s"no finish after $maxCycles cycles: ${hits.size}/${rays.size} hits")
      if (cycle - lastProgress > stallLimit)
        throw new AssertionError(s"deadlock: no ray entered or left for $stallLimit cycles at cycle $cycle " +
          s"(${hits.size}/${rays.size} hits, in flight: ${inFlight.toSeq.sorted.take(16).mkString(",")})")
      val f = io.flags.peek().litValue
      def bit(name: String) = f.testBit(SimTop.flagFields.indexOf(name))

      val offer = next < rays.size && !(env.rayGap > 0 && rnd.nextDouble() < env.rayGap)
      if (offer) rayNow = set(io.ray, SimTop.packRay(rays(next)), rayNow)
      val hitReady = !(env.hitRefuse > 0 && rnd.nextDouble() < env.hitRefuse)
      if (bit("hitsValid") && hitReady) {
        val w = io.hit.peek().litValue
        val h = HitRecord(
          st(w, "hitNumber").toLong,
          st(w, "hitHit") == 1,
          st(w, "hitT").toLong,
          st(w, "hitU").toLong,
          st(w, "hitV").toLong,
          st(w, "hitPrim").toLong,
          st(w, "hitErrors").toInt
        )
        if (!inFlight.remove(h.number))
          throw new AssertionError(
            s"cycle $cycle: hit for ray ${h.number}, which is not in flight (lost or duplicated)"
          )
        hits += h
        lastProgress = cycle
        // After this cycle's step the counters include it; taken before the step, they stop at the cycle before,
        // at both ends alike.
        if (windowAt.exists { case (a, b) => hits.size == a || hits.size == b })
          snapshots += Snapshot(hits.size, cycle, perf(dut), dram.map(_.stats(cycle)))
      }
      if (offer && bit("raysReady")) {
        inFlight += rays(next).number
        next += 1
        lastProgress = cycle
      }
      def port(d: MemPortDriver, p: String, req: UInt, addrBits: Int): (Boolean, Option[(Int, BigInt)]) = {
        val valid = bit(p + "ReqValid")
        val word = if (valid) req.peek().litValue else BigInt(0)
        val addr = (word & ((BigInt(1) << addrBits) - 1)).toLong
        val ready = d.ready(valid, addr)
        val resp = d.response
        d.commit(valid, ready, addr, (word >> addrBits).toInt, resp.isDefined && bit(p + "RespReady"))
        (ready, resp)
      }
      val (nodeReady, nodeResp) = port(node, "node", io.nodeReq, dut.accel.io.nodeMem.p.addrBits)
      val (triReady, triResp) = port(tri, "tri", io.triReq, dut.accel.io.triMem.p.addrBits)
      nodeRespNow = set(io.nodeResp, SimTop.packResp(tagN, nodeResp), nodeRespNow)
      triRespNow = set(io.triResp, SimTop.packResp(tagT, triResp), triRespNow)
      val ctrl = Seq(offer, hitReady, nodeReady, triReady).zipWithIndex.map { case (b, i) => if (b) 1 << i else 0 }.sum
      ctrlNow = set(io.ctrl, BigInt(ctrl), ctrlNow)
      if (bit("broken")) throw new AssertionError(s"cycle $cycle: the design flagged a lost or duplicated ray")
      dut.clock.step(); node.tick(); tri.tick()
      cycle += 1
      if ((cycle & 0xfff) == 0) progress(hits.size)
    }
    val window = snapshots.toSeq match { case Seq(a, b) => Some((a, b)); case _ => None }
    RunResult(hits.toSeq, cycle, perf(dut), node.model.stats, tri.model.stats, dram.map(_.stats(cycle)), window)
  }

  def perf[T <: Data](dut: SimTop[T]): Map[String, BigInt] =
    dut.io.perf.elements.map { case (name, d) => name -> d.asInstanceOf[UInt].peek().litValue }.toMap
}
