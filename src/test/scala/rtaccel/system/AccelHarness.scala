package rtaccel.system

import chisel3._
import chiseltest._
import rtaccel.RtAccel
import rtaccel.golden.{HitRecord, RayRecord}
import rtaccel.mem.{MemPortHarness, MemStats, MemoryParams, MemorySystemModel}
import rtaccel.scene.MemoryImage

import scala.collection.mutable
import scala.util.Random

/** How the world around the accelerator behaves during a run. */
final case class Environment(
    node: MemoryParams,
    tri: MemoryParams,
    /** Chance that the host offers no ray in a cycle. */
    rayGap: Double = 0.0,
    /** Chance that the consumer refuses a hit in a cycle. */
    hitRefuse: Double = 0.0,
    /** Chance that a memory port refuses a request on top of its own limits. */
    memRefuse: Double = 0.0,
    seed: Long = 1
)

final case class RunResult(hits: Seq[HitRecord], cycles: Long, perf: Map[String, BigInt], node: MemStats, tri: MemStats)

/** Runs rays through an RtAccel cycle by cycle (single-threaded, no `fork`),
  * with memory models on both ports. Fails loudly if a hit comes for a ray
  * not in flight, comes twice, if the design flags itself broken, or if no
  * progress is made for `stallLimit` cycles (a deadlock).
  */
object AccelHarness {
  def run[T <: Data](dut: RtAccel[T], img: MemoryImage, rays: IndexedSeq[RayRecord], env: Environment,
      maxCycles: Long = 10000000L, stallLimit: Int = 20000, progress: Long => Unit = _ => ()): RunResult = {
    val rnd = new Random(env.seed)
    val nodeMem = new MemPortHarness(dut.io.nodeMem, new MemorySystemModel(img, 32, env.node, "node"), env.memRefuse, new Random(rnd.nextLong()))
    val triMem  = new MemPortHarness(dut.io.triMem, new MemorySystemModel(img, 48, env.tri, "triangle"), env.memRefuse, new Random(rnd.nextLong()))
    dut.io.nodeBase.poke(img.nodeOffset.U)
    dut.io.triBase.poke(img.triOffset.U)
    dut.clock.setTimeout(0)

    val byNumber = rays.map(r => r.number -> r).toMap
    require(byNumber.size == rays.size, "ray numbers must be distinct")
    val inFlight = mutable.Set.empty[Long]
    val hits = mutable.ArrayBuffer.empty[HitRecord]
    var next = 0
    var cycle = 0L
    var lastProgress = 0L
    while (hits.size < rays.size) {
      if (cycle >= maxCycles) throw new AssertionError(s"no finish after $maxCycles cycles: ${hits.size}/${rays.size} hits")
      if (cycle - lastProgress > stallLimit)
        throw new AssertionError(s"deadlock: no ray entered or left for $stallLimit cycles at cycle $cycle " +
          s"(${hits.size}/${rays.size} hits, in flight: ${inFlight.toSeq.sorted.take(16).mkString(",")})")
      val offer = next < rays.size && !(env.rayGap > 0 && rnd.nextDouble() < env.rayGap)
      dut.io.rays.valid.poke(offer.B)
      if (offer) pokeRay(dut, rays(next))
      val hitReady = !(env.hitRefuse > 0 && rnd.nextDouble() < env.hitRefuse)
      dut.io.hits.ready.poke(hitReady.B)
      if (dut.io.hits.valid.peek().litToBoolean && hitReady) {
        val h = peekHit(dut)
        if (!inFlight.remove(h.number))
          throw new AssertionError(s"cycle $cycle: hit for ray ${h.number}, which is not in flight (lost or duplicated)")
        hits += h
        lastProgress = cycle
      }
      if (offer && dut.io.rays.ready.peek().litToBoolean) {
        inFlight += rays(next).number
        next += 1
        lastProgress = cycle
      }
      nodeMem.drive(); triMem.drive()
      if (dut.io.broken.peek().litToBoolean) throw new AssertionError(s"cycle $cycle: the design flagged a lost or duplicated ray")
      dut.clock.step(); nodeMem.tick(); triMem.tick()
      cycle += 1
      if ((cycle & 0xffff) == 0) progress(cycle)
    }
    RunResult(hits.toSeq, cycle, perf(dut), nodeMem.model.stats, triMem.model.stats)
  }

  private def pokeRay[T <: Data](dut: RtAccel[T], r: RayRecord): Unit = {
    val b = dut.io.rays.bits
    b.number.poke(r.number.U)
    for (a <- 0 until 3) { b.ray.origin(a).poke(r.origin(a).U); b.ray.dir(a).poke(r.dir(a).U) }
    b.ray.tmin.poke(r.tmin.U); b.ray.tmax.poke(r.tmax.U); b.shadow.poke(r.shadow.B)
  }

  private def peekHit[T <: Data](dut: RtAccel[T]): HitRecord = {
    val h = dut.io.hits.bits
    HitRecord(h.number.peek().litValue.toLong, h.hit.peek().litToBoolean, h.t.peek().litValue.toLong,
      h.u.peek().litValue.toLong, h.v.peek().litValue.toLong, h.prim.peek().litValue.toLong, h.errors.peek().litValue.toInt)
  }

  def perf[T <: Data](dut: RtAccel[T]): Map[String, BigInt] =
    dut.io.perf.elements.map { case (name, d) => name -> d.asInstanceOf[UInt].peek().litValue }.toMap
}
