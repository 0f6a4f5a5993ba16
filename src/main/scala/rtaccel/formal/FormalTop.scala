package rtaccel.formal

import chisel3._
import chisel3.util._
import rtaccel.fetch.RayIn
import rtaccel.{AccelConfig, RtAccel}
import rtaccel.bvh.BvhLayout

/** The environment of a proof: memory latency and stall bounds, how long the
  * host may refuse a hit, and the scenes memory may hold. The bound every ray
  * must leave within is derived from these (ResponseBound), not chosen.
  *
  * @param memLatency  each memory answers 1..memLatency cycles after it took the request
  * @param memStall    a memory refuses a request at most this many cycles in a row
  * @param hitStall    the host refuses a hit at most this many cycles in a row
  * @param scene       the rule node records obey (SceneRule)
  */
case class FormalEnv(memLatency: Int, memStall: Int, hitStall: Int, scene: SceneRule = SceneRule.ChildrenFollow)

/** RtAccel in a formal environment (docs/formal.md): rays with free data and
  * host numbers, memories that answer within a bound, a host that takes hits
  * within a bound, and a monitor that follows every ray by its host number.
  *
  * Environment rules are `assume`s; the monitor's end-to-end properties and
  * the design's own assertions are `assert`s.
  *  - exactly_once: a hit only for a number in flight (so no ray leaves twice
  *    and no ray is made up); with bounded_response, each leaves exactly once.
  *  - bounded_response: a ray in flight has been in for at most `responseBound` cycles.
  *  - in_flight_bound: at most numRayIds rays inside.
  *
  * Scene rule (an assumption, SceneRule): an inner child's index
  * is greater than its parent's, as in every image nori-bridge writes
  * (children follow their parent), so traversal ends; without it a node
  * could name itself and a ray would rightly never finish.
  *
  * @param responseBound ResponseBound(cfg, dp, env), or a probe's cut bound
  * @param tag           the module name's suffix (the case name)
  */
class FormalTop(cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv, responseBound: Int, tag: String) extends Module {
  require(cfg.layout.isInstanceOf[BvhLayout.Wide], "FormalTop: the scene rule is written for the wide layouts")
  val io = IO(new Bundle {})
  override def desiredName = s"FormalTop_$tag"

  private val accel = Module(new RtAccel(cfg, dp))
  accel.io.nodeBase := 0.U
  accel.io.triBase := 0.U

  private val nodeMem = Module(new FormalMemEnv(accel.io.nodeMem.p, env.memLatency, env.memStall))
  private val triMem = Module(new FormalMemEnv(accel.io.triMem.p, env.memLatency, env.memStall))
  nodeMem.io.mem <> accel.io.nodeMem
  triMem.io.mem <> accel.io.triMem

  // ---- Scene rule: node k's inner children are nodes > k (node base is 0) ----
  private val nodeIdx = nodeMem.io.respAddr >> log2Ceil(cfg.layout.nodeBytes)
  private val record = nodeMem.io.mem.resp.bits.data
  for (s <- 0 until cfg.boxLanes) {
    val (w0, w1) = (record(256 * s + 31, 256 * s), record(256 * s + 63, 256 * s + 32))
    assume(!(nodeMem.io.mem.resp.valid && w0 === 0.U && w1 <= nodeIdx), s"scene_children_follow: slot $s")
  }

  // ---- Host: free rays, numbers unique among the rays in flight ----
  private val slots = 2 * cfg.numRayIds
  private val numBits = log2Ceil(slots)
  private val rays = accel.io.rays
  private val number = FormalAnySeq(UInt(numBits.W))
  rays.valid := FormalAnySeq(Bool())
  rays.bits := FormalAnySeq(new RayIn)
  rays.bits.number := number
  private val inFlightReg = RegInit(VecInit(Seq.fill(slots)(false.B)))
  private val ageReg = RegInit(VecInit(Seq.fill(slots)(0.U(log2Ceil(responseBound + 2).W))))
  assume(!(rays.valid && inFlightReg(number)), "host_numbers_unique")

  // ---- Host: takes a hit after at most hitStall refusals in a row ----
  private val hits = accel.io.hits
  private val hitStallReg = RegInit(0.U(log2Ceil(env.hitStall + 1).max(1).W))
  hits.ready := FormalAnySeq(Bool())
  assume(!(hits.valid && hitStallReg === env.hitStall.U) || hits.ready, "host_takes_hits")
  when(hits.valid && !hits.ready) { hitStallReg := hitStallReg + 1.U }.otherwise { hitStallReg := 0.U }

  // ---- Monitor ----
  private val hitNum = hits.bits.number
  assert(
    !hits.fire || (hitNum < slots.U && inFlightReg(hitNum(numBits - 1, 0))),
    "exactly_once: a hit for a ray not in flight"
  )
  for (i <- 0 until slots) {
    val in = rays.fire && number === i.U
    val out = hits.fire && hitNum === i.U
    when(in) { inFlightReg(i) := true.B; ageReg(i) := 0.U }
    when(out) { inFlightReg(i) := false.B }
    when(inFlightReg(i) && !out && ageReg(i) <= responseBound.U) { ageReg(i) := ageReg(i) + 1.U }
    assert(
      !inFlightReg(i) || ageReg(i) < responseBound.U,
      s"bounded_response: ray number $i in flight for ${responseBound} cycles"
    )
  }
  assert(PopCount(inFlightReg) <= cfg.numRayIds.U, "in_flight_bound: more rays inside than IDs")
}
