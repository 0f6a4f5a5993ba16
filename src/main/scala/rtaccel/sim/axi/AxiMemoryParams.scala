package rtaccel.sim.axi

import rtaccel.sim.mem.{FabricClock, LatencyNs, MemoryKind}

/** How an AxiMemoryModel behaves.
  *
  * @param beatBytes   data width in bytes (64: the MIG's 512-bit user interface)
  * @param latency     DRAM round trip per burst, uniform in [lo, hi] ns (seeded)
  * @param ddr         the DRAM whose bandwidth and burst charge the model shares (DramModel)
  * @param readyProb   probability that arready, awready and wready are each high in a cycle
  * @param validProb   probability that a beat ready on R (or a response on B) is offered in a cycle
  * @param reorder     answer bursts of different IDs in any order (in order within an ID)
  * @param interleave  interleave R beats of different IDs (else a burst goes out whole)
  * @param maxReads    read bursts accepted and not finished; arready is low at the limit
  * @param maxWrites   write bursts accepted and not answered on B; awready is low at the limit
  * @param errorAt     answer SLVERR for a burst whose address this is true of (default: never)
  * @param seed        seed of every random choice (the test prints it)
  */
final case class AxiMemoryParams(
    beatBytes: Int = 64,
    latency: LatencyNs = MemoryKind.Ddr.DefaultLatency,
    ddr: MemoryKind.Ddr = MemoryKind.Ddr(),
    readyProb: Double = 1.0,
    validProb: Double = 1.0,
    reorder: Boolean = true,
    interleave: Boolean = false,
    maxReads: Int = 64,
    maxWrites: Int = 64,
    errorAt: Long => Boolean = _ => false,
    seed: Long = 1
) {
  require(Integer.bitCount(beatBytes) == 1, s"AxiMemoryParams: beatBytes must be a power of two, got $beatBytes")
  require(
    readyProb > 0 && readyProb <= 1 && validProb > 0 && validProb <= 1,
    s"AxiMemoryParams: probabilities must be in (0, 1]"
  )
  require(maxReads >= 1 && maxWrites >= 1, s"AxiMemoryParams: maxReads and maxWrites must be >= 1")
  def clock: FabricClock = ddr.clock

  /** A harsh environment for tests: long random latency, stalls and gaps on every channel, reordering and interleaving. */
  def harsh(seed: Long): AxiMemoryParams =
    copy(
      latency = LatencyNs(20, 400),
      readyProb = 0.6,
      validProb = 0.7,
      interleave = true,
      maxReads = 24,
      maxWrites = 8,
      seed = seed
    )
}
