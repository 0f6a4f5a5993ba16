package rtaccel.testutil

import scala.util.Random

/** Seeded randomness for tests. Every random test draws from one seed, which
  * a failure message always names; `RTACCEL_SEED=<n>` replays it.
  */
object Seeded {

  /** The seed for a test: `RTACCEL_SEED` if set, else a stable hash of its name. */
  def seedFor(testName: String): Long =
    sys.env.get("RTACCEL_SEED").map(_.trim.toLong).getOrElse(testName.hashCode.toLong & 0xffffffffL)

  /** Runs `body` with a seeded Random, printing the seed; on failure, rethrows with the seed in the message. */
  def apply[T](testName: String)(body: Random => T): T = {
    val seed = seedFor(testName)
    println(s"[$testName] seed $seed (replay: RTACCEL_SEED=$seed)")
    try body(new Random(seed))
    catch {
      case e: Throwable =>
        throw new AssertionError(s"[$testName] failed with seed $seed (replay: RTACCEL_SEED=$seed): ${e.getMessage}", e)
    }
  }
}
