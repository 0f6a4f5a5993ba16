package rtaccel.mem

/** How long the memory takes to answer one transfer, in cycles. */
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

  /** Parses `100` or `50-300`, as given to `make regress MEM_LATENCY=...`. */
  def parse(s: String): Latency = s.trim.split("-").map(_.trim) match {
    case Array(n) if n.forall(_.isDigit)                    => Fixed(n.toInt)
    case Array(a, b) if (a + b).forall(_.isDigit) && a.nonEmpty => Uniform(a.toInt, b.toInt)
    case _ => throw new IllegalArgumentException(s"memory latency '$s': expected N or LO-HI, e.g. 100 or 50-300")
  }
}

/** A non-blocking cache in front of DRAM, after Asiatici's miss-optimized
  * memory system: misses to a line already being fetched merge into its MSHR
  * instead of fetching it again, so many rays waiting on one node cost one
  * DRAM transfer.
  */
case class CacheParams(lineBytes: Int = 64, capacityBytes: Int = 32 * 1024, ways: Int = 4, mshrs: Int = 16, hitLatency: Int = 2) {
  require(Integer.bitCount(lineBytes) == 1 && lineBytes >= 8, s"CacheParams: lineBytes must be a power of two >= 8, got $lineBytes")
  require(ways >= 1, s"CacheParams: ways must be >= 1, got $ways")
  require(capacityBytes % (lineBytes * ways) == 0 && capacityBytes > 0,
    s"CacheParams: capacityBytes ($capacityBytes) must be a positive multiple of lineBytes*ways (${lineBytes * ways})")
  require(mshrs >= 1, s"CacheParams: mshrs must be >= 1, got $mshrs")
  require(hitLatency >= 1, s"CacheParams: hitLatency must be >= 1, got $hitLatency")
  val sets: Int = capacityBytes / (lineBytes * ways)
}

/** One port's memory system.
  *
  * @param latency        DRAM latency per transfer
  * @param maxOutstanding requests accepted but not yet answered; at the limit the port stalls
  * @param bytesPerCycle  DRAM return bandwidth shared by all transfers of this port
  * @param inOrder        answer in request order (else as soon as each is ready)
  * @param cache          optional non-blocking cache
  * @param seed           seed of the latency generator
  */
case class MemoryParams(
    latency: Latency = Latency.Fixed(10),
    maxOutstanding: Int = 64,
    bytesPerCycle: Int = 16,
    inOrder: Boolean = false,
    cache: Option[CacheParams] = None,
    seed: Long = 1
) {
  require(maxOutstanding >= 1, s"MemoryParams: maxOutstanding must be >= 1, got $maxOutstanding")
  require(bytesPerCycle >= 1, s"MemoryParams: bytesPerCycle must be >= 1, got $bytesPerCycle")
  def describe: String =
    s"latency=${latency.describe} outstanding=$maxOutstanding bw=${bytesPerCycle}B/cycle ${if (inOrder) "in-order" else "out-of-order"}" +
      cache.fold("")(c => s" cache=${c.capacityBytes}B/${c.ways}way/${c.lineBytes}B-lines/${c.mshrs}mshr")
}
