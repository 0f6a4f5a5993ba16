package rtaccel.formal

import rtaccel.system.{HitDma, SystemConfig}

/** The system's formal environment (docs/formal.md, "System level").
  *
  * @param readLatency  an AXI read burst older than this many cycles takes the R channel (any overdue one)
  * @param stall        the slave refuses AR, AW or W at most this many cycles in a row; the core stub refuses a memory answer at most this many
  * @param bLatency     a written beat's B response comes after at most this many refusals in a row
  * @param maxRays      the batch holds 1..maxRays rays (the environment chooses)
  * @param bursts       read bursts the slave holds at once (it refuses AR when full)
  */
final case class SystemEnv(readLatency: Int, stall: Int, bLatency: Int, maxRays: Int, bursts: Int)

/** One system proof: the configuration, environment and depth. `window`: the host first sets a DMA window of
  * its choice (WINDOW_BASE, WINDOW_LIMIT, free), and the case checks `window_kept` instead of the batch's
  * end-to-end properties (a refused burst stops the batch, so DONE no longer means every ray). */
final case class SystemCase(name: String, sys: SystemConfig, env: SystemEnv, depth: Int, window: Boolean = false)

object SystemCase {

  /** 1 core of 2 ray IDs (the core proofs' narrow configuration, FormalCase.small), 12-bit addresses (the AXI
    * minimum), 2 AXI ID bits (3 read slots + the store's fill), a 64-byte node store (one node), no triangle store,
    * 2 ray blocks in flight, a 2-deep hit queue, 2 pair slots. */
  val sys2: SystemConfig = {
    val core = FormalCase.small(2).copy(addrBits = 12)
    SystemConfig(
      core = core,
      cores = 1,
      axiDataBits = 512,
      axiAddrBits = 12,
      axiIdBits = 2,
      nodeStoreBytes = 64,
      triStoreBytes = 0,
      raysPerBlock = 4,
      rayBlockTags = 2,
      hitQueue = 2,
      hitPairSlots = Some(2)
    )
  }
  val env: SystemEnv = SystemEnv(readLatency = 3, stall = 1, bLatency = 2, maxRays = 8, bursts = 4)

  /** w1's depth: the two window writes, LOAD_SCENE, the header read and the fills; the batch's reads lie past it
    * (docs/formal.md, "System level"). */
  val all: Seq[SystemCase] =
    Seq(SystemCase("s1", sys2, env, depth = 44), SystemCase("w1", sys2, env, depth = 30, window = true))

  /** The units' environment, from s1's: memory and AXI slave as env (L = 3, S = 1, 4 bursts), the core and
    * the read clients refusing at most env.stall = 1 cycle in a row. */
  val unitEnv: UnitEnv = UnitEnv(
    memLatency = env.readLatency,
    stall = env.stall,
    takeStall = env.stall,
    readLatency = env.readLatency,
    bursts = env.bursts
  )

  /** Each system unit alone (FormalSystemUnits), in s1's configuration, checked by BMC 8 steps past its bound. */
  val units: Seq[UnitCase] = {
    val e = unitEnv
    val rays = env.maxRays
    val rd = SystemUnitBound.rayDma(sys2, e, rays)
    val hd = SystemUnitBound.hitDma(sys2, e)
    val beats = FormalReadEngineTop.maxBeats(sys2)
    val re = SystemUnitBound.readEngine(beats, FormalReadEngineTop.slots(sys2), e)
    Seq(
      UnitCase(
        "raydma",
        () => new FormalRayDmaTop(sys2, e, rays, "raydma"),
        rd,
        rd + 8,
        deep = true,
        terms = (1 to rays).map(r => s"$r rays: ${SystemUnitBound.rayDma(sys2, e, r)}").mkString(", ")
      ),
      UnitCase(
        "hitdma",
        () => new FormalHitDmaTop(sys2, e, rays, "hitdma"),
        hd,
        hd + 8,
        deep = true,
        terms =
          s"after the batch's last hit: (input slice ${HitDma.InSlice} + decision stage 1 + hit queue ${sys2.hitQueue} + pair slots ${sys2.pairSlots}) x (writer refusals ${SystemUnitBound.writeStall(e)} + 1) + 7"
      ),
      // bmc3's frames on this harness double from frame 15 (frame 18: 130 s of CPU), so BMC stops at 18, short of
      // the bound (its bounded response is VACUOUS there, the log says so); the safety properties hold to 18.
      UnitCase(
        "readeng",
        () => new FormalReadEngineTop(sys2, e, "readeng"),
        re,
        18,
        deep = true,
        terms =
          s"slots ${FormalReadEngineTop.slots(sys2)}, max beats $beats, L ${e.readLatency}, S ${e.stall}, H ${e.takeStall}"
      )
    )
  }
}
