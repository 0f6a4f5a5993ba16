package rtaccel.regress

import rtaccel.mem.{CacheParams, Latency, MemoryParams}

import java.nio.file.{Path, Paths}

/** `make regress` options, as `--key value` pairs (the Makefile maps its
  * variables onto them). Every value is checked here, with a message naming it.
  */
final case class RegressArgs(
    pkg: Path,
    out: Path,
    float: String = "e8m23",
    triangle: String = "watertight",
    rounding: String = "rne",
    memLatency: Latency = Latency.Fixed(100),
    bytesPerCycle: Int = 16,
    outstanding: Int = 64,
    cache: Option[CacheParams] = None,
    numRayIds: Int = 64,
    stackDepth: Option[Int] = None,
    maxRays: Option[Int] = None,
    bridge: Path = Paths.get("nori-bridge/target/release/nori-bridge"),
    waves: Boolean = false,
    strict: Boolean = false,
    /** Size stack depth, index widths and leaf size to the scene. */
    sized: Boolean = false,
    seed: Long = 1
) {
  def memory(seedOffset: Long): MemoryParams =
    MemoryParams(memLatency, outstanding, bytesPerCycle, inOrder = false, cache, seed + seedOffset)
}

object RegressArgs {
  val usage: String =
    """usage: Regress --package DIR --out DIR [--float e8m23] [--triangle moller|watertight] [--rounding rne|conservative]
      |       [--mem-latency 100|50-300] [--bytes-per-cycle 16] [--outstanding 64] [--cache KiB] [--ids 64]
      |       [--stack N] [--rays N] [--bridge PATH] [--waves 0|1] [--strict 0|1] [--size 0|1] [--seed N]""".stripMargin

  def parse(args: Seq[String]): RegressArgs = {
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    val kv = args.grouped(2).map(p => p(0) -> p(1)).toMap
    def int(k: String, v: String, min: Int): Int =
      v.toIntOption.filter(_ >= min).getOrElse(fail(s"$k: '$v' is not a whole number >= $min"))
    def flag(k: String, v: String): Boolean = v match {
      case "1" | "true" => true; case "0" | "false" | "" => false; case _ => fail(s"$k: '$v' (0 or 1)")
    }
    var a = RegressArgs(Paths.get(kv.getOrElse("--package", fail("--package is required"))),
      Paths.get(kv.getOrElse("--out", fail("--out is required"))))
    for ((k, v) <- kv) k match {
      case "--package" | "--out" => ()
      case "--float"           => a = a.copy(float = v)
      case "--triangle"        => a = a.copy(triangle = v)
      case "--rounding"        => a = a.copy(rounding = v)
      case "--mem-latency"     => a = a.copy(memLatency = try Latency.parse(v) catch { case e: IllegalArgumentException => fail(e.getMessage) })
      case "--bytes-per-cycle" => a = a.copy(bytesPerCycle = int(k, v, 1))
      case "--outstanding"     => a = a.copy(outstanding = int(k, v, 1))
      case "--cache"           => a = a.copy(cache = if (v == "0" || v.isEmpty) None else Some(CacheParams(capacityBytes = int(k, v, 1) * 1024)))
      case "--ids"             => a = a.copy(numRayIds = int(k, v, 2))
      case "--stack"           => a = a.copy(stackDepth = if (v.isEmpty) None else Some(int(k, v, 1)))
      case "--rays"            => a = a.copy(maxRays = if (v.isEmpty) None else Some(int(k, v, 1)))
      case "--bridge"          => a = a.copy(bridge = Paths.get(v))
      case "--waves"           => a = a.copy(waves = flag(k, v))
      case "--strict"          => a = a.copy(strict = flag(k, v))
      case "--size"            => a = a.copy(sized = flag(k, v))
      case "--seed"            => a = a.copy(seed = v.toLongOption.getOrElse(fail(s"--seed: '$v'")))
      case other               => fail(s"unknown option '$other'")
    }
    a
  }

  private def fail(why: String): Nothing = throw new IllegalArgumentException(s"$why\n$usage")
}
