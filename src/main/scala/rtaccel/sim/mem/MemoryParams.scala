package rtaccel.sim.mem

/** How long the memory takes to answer one transfer, in fabric cycles. */
sealed trait Latency {
  def min: Int
  def describe: String
}
object Latency {
  case class Fixed(cycles: Int) extends Latency {
    require(cycles >= 1, s"Latency.Fixed: cycles must be >= 1, got $cycles")
    def min: Int = cycles
    def describe: String = s"$cycles"
  }

  /** Uniform in [lo, hi], drawn from the model's seeded generator. */
  case class Uniform(lo: Int, hi: Int) extends Latency {
    require(lo >= 1 && hi >= lo, s"Latency.Uniform: need 1 <= lo <= hi, got [$lo, $hi]")
    def min: Int = lo
    def describe: String = s"$lo-$hi"
  }
}

/** A memory latency as a datasheet or a user states it, in nanoseconds:
  * fixed (`lo == hi`) or uniform in [lo, hi]. `cycles` converts it at a clock.
  */
final case class LatencyNs(lo: Int, hi: Int) {
  require(lo >= 1 && hi >= lo, s"memory latency: need 1 <= lo <= hi ns, got [$lo, $hi]")
  def cycles(clock: FabricClock): Latency =
    if (lo == hi) Latency.Fixed(clock.cycles(lo)) else Latency.Uniform(clock.cycles(lo), clock.cycles(hi))
  def describe: String = if (lo == hi) s"$lo ns" else s"$lo-$hi ns"
}
object LatencyNs {

  /** Parses `100` or `80-300` (ns), as given to `make regress MEM_LATENCY=...`. */
  def parse(s: String): LatencyNs = {
    def ns(x: String) = x.trim.toIntOption.filter(_ >= 1)
    s.split("-", -1) match {
      case Array(n) if ns(n).isDefined => LatencyNs(ns(n).get, ns(n).get)
      case Array(a, b) if ns(a).isDefined && ns(b).isDefined && ns(a).get <= ns(b).get =>
        LatencyNs(ns(a).get, ns(b).get)
      case _ => throw new IllegalArgumentException(
          s"memory latency '$s': expected N or LO-HI in ns (whole numbers, 1 <= LO <= HI), e.g. 100 or 80-300"
        )
    }
  }
}

/** A non-blocking cache in front of DRAM, after Asiatici's miss-optimized
  * memory system: misses to a line already being fetched merge into its MSHR
  * instead of fetching it again, so many rays waiting on one node cost one
  * DRAM transfer.
  */
case class CacheParams(
    lineBytes: Int = 64,
    capacityBytes: Int = 32 * 1024,
    ways: Int = 4,
    mshrs: Int = 16,
    hitLatency: Int = 2
) {
  require(
    Integer.bitCount(lineBytes) == 1 && lineBytes >= 8,
    s"CacheParams: lineBytes must be a power of two >= 8, got $lineBytes"
  )
  require(ways >= 1, s"CacheParams: ways must be >= 1, got $ways")
  require(
    capacityBytes % (lineBytes * ways) == 0 && capacityBytes > 0,
    s"CacheParams: capacityBytes ($capacityBytes) must be a positive multiple of lineBytes*ways (${lineBytes * ways})"
  )
  require(mshrs >= 1, s"CacheParams: mshrs must be >= 1, got $mshrs")
  require(hitLatency >= 1, s"CacheParams: hitLatency must be >= 1, got $hitLatency")
  val sets: Int = capacityBytes / (lineBytes * ways)
}

/** One port's view of the memory system. Bandwidth is not a port parameter:
  * it belongs to the store behind the port (`Backing`), which for DRAM both
  * ports share.
  *
  * @param latency        per transfer, in cycles (from ns through `LatencyNs.cycles`)
  * @param maxOutstanding requests accepted but not yet answered; at the limit the port stalls
  * @param inOrder        answer in request order (else as soon as each is ready)
  * @param cache          optional non-blocking cache, private to the port
  * @param seed           seed of the latency generator
  */
case class MemoryParams(
    latency: Latency = Latency.Fixed(10),
    maxOutstanding: Int = 64,
    inOrder: Boolean = false,
    cache: Option[CacheParams] = None,
    seed: Long = 1
) {
  require(maxOutstanding >= 1, s"MemoryParams: maxOutstanding must be >= 1, got $maxOutstanding")
  def describe: String =
    s"latency=${latency.describe} cycles, outstanding=$maxOutstanding, ${if (inOrder) "in-order" else "out-of-order"}" +
      cache.fold("")(c => s", cache=${c.capacityBytes}B/${c.ways}way/${c.lineBytes}B-lines/${c.mshrs}mshr")
}
