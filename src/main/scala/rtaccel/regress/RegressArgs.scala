package rtaccel.regress

import java.nio.file.{Path, Paths}
import rtaccel.sim.Environment
import rtaccel.sim.mem.{CacheParams, FabricClock, Latency, LatencyNs, MemoryKind, MemoryParams}

/** `make regress` options, as `--key value` pairs (the Makefile maps its
  * variables onto them). Every value is checked here, with a message naming it.
  */
final case class RegressArgs(
    pkg: Path,
    out: Path,
    float: String = "e8m23",
    /** BOX_FLOAT= / TRI_FLOAT=: one unit's format; "" means FLOAT's. */
    boxFloat: String = "",
    triFloat: String = "",
    triangle: String = "watertight",
    /** Conservative (outward-rounded) boxes: no false miss from box rounding (see docs/reports/speed-vs-error.md). */
    rounding: String = "conservative",
    /** `fp32` or `grid` (BoxTest: quantized layouts' child boxes in the node's grid). */
    boxTest: String = "fp32",
    /** `ddr` (one DRAM behind both ports) or `onchip` (BRAM per port). */
    memory: String = "ddr",
    /** DRAM latency in ns; None: `MemoryKind.Ddr.DefaultLatency`. Not allowed on chip. */
    memLatency: Option[LatencyNs] = None,
    fabricMhz: Double = FabricClock.DefaultMhz,
    outstanding: Int = 64,
    cache: Option[CacheParams] = None,
    numRayIds: Int = rtaccel.AccelConfig.zc706.numRayIds,
    stackDepth: Option[Int] = None,
    maxRays: Option[Int] = None,
    bridge: Path = Paths.get("nori-bridge/target/release/nori-bridge"),
    waves: Boolean = false,
    strict: Boolean = false,
    /** Size stack depth, index widths and leaf size to the scene. */
    sized: Boolean = false,
    seed: Long = 1,
    /** `chiseltest` (the core, the Scala memory model on its ports) or `cpp` (the system top under sw/sim/). */
    sim: String = "chiseltest"
) {
  def clock: FabricClock = FabricClock(fabricMhz)
  def memoryKind: MemoryKind = memory match {
    case "onchip" => MemoryKind.OnChip
    case _        => MemoryKind.Ddr(clock)
  }

  /** Per-port latency in cycles: the DRAM's ns at the fabric clock, or BRAM's fixed cycles. */
  def latencyCycles: Latency = memoryKind match {
    case MemoryKind.OnChip => Latency.Fixed(MemoryKind.OnChip.LatencyCycles)
    case _                 => memLatency.getOrElse(MemoryKind.Ddr.DefaultLatency).cycles(clock)
  }
  def port(seedOffset: Long): MemoryParams =
    MemoryParams(latencyCycles, outstanding, inOrder = false, cache, seed + seedOffset)

  /** Both ports and the store behind them, seeded from `seed`. */
  def environment: Environment = Environment(port(0), port(1), memoryKind, seed = seed)
  def describeMemory: String = memoryKind match {
    case MemoryKind.OnChip => s"${MemoryKind.OnChip.describe}; ${port(0).describe}"
    case d =>
      s"${d.describe}; latency ${memLatency.getOrElse(MemoryKind.Ddr.DefaultLatency).describe}; ${port(0).describe}"
  }
}

object RegressArgs {

  /** The box and triangle formats `a` asks for: BOX_FLOAT= / TRI_FLOAT= where given, FLOAT= otherwise. */
  def formats(a: RegressArgs): (String, String) =
    (if (a.boxFloat.nonEmpty) a.boxFloat else a.float, if (a.triFloat.nonEmpty) a.triFloat else a.float)

  val usage: String =
    """usage: Regress --package DIR --out DIR [--float e8m23] [--box-float eXmY] [--tri-float eXmY] [--triangle moller|watertight] [--rounding conservative|rne]
      |       [--box-test fp32|grid (grid: 4q/8q images only)]
      |       [--memory ddr|onchip] [--mem-latency NS|LO-HI (ddr only; default 100)] [--fabric-mhz 200]
      |       [--outstanding 64] [--cache KiB (ddr only)] [--ids 64]
      |       [--stack N] [--rays N] [--bridge PATH] [--waves 0|1] [--strict 0|1] [--size 0|1] [--seed N]
      |       [--sim chiseltest|cpp]""".stripMargin

  def parse(args: Seq[String]): RegressArgs = {
    if (args.size % 2 != 0) fail(s"options come in pairs: ${args.mkString(" ")}")
    val kv = args.grouped(2).map(p => p(0) -> p(1)).toMap
    def int(k: String, v: String, min: Int): Int =
      v.toIntOption.filter(_ >= min).getOrElse(fail(s"$k: '$v' is not a whole number >= $min"))
    def flag(k: String, v: String): Boolean = v match {
      case "1" | "true" => true; case "0" | "false" | "" => false; case _ => fail(s"$k: '$v' (0 or 1)")
    }
    var a = RegressArgs(
      Paths.get(kv.getOrElse("--package", fail("--package is required"))),
      Paths.get(kv.getOrElse("--out", fail("--out is required")))
    )
    for ((k, v) <- kv) k match {
      case "--package" | "--out" => ()
      case "--float"             => a = a.copy(float = v)
      case "--box-float"         => a = a.copy(boxFloat = v)
      case "--tri-float"         => a = a.copy(triFloat = v)
      case "--triangle"          => a = a.copy(triangle = v)
      case "--rounding"          => a = a.copy(rounding = v)
      case "--box-test"          => a = a.copy(boxTest = wrap(k)(rtaccel.BoxTest.parse(v)).name)
      case "--memory"            => a = a.copy(memory = wrap(k)(MemoryKind.parse(v)).name)
      case "--mem-latency"       => a = a.copy(memLatency = if (v.isEmpty) None else Some(wrap(k)(LatencyNs.parse(v))))
      case "--fabric-mhz" => a = a.copy(fabricMhz =
          v.toDoubleOption.filter(x => x > 0 && !x.isInfinite)
            .getOrElse(fail(s"$k: '$v' is not a clock frequency in MHz (a number > 0, e.g. 200)"))
        )
      case "--outstanding" => a = a.copy(outstanding = int(k, v, 1))
      case "--cache" =>
        a = a.copy(cache = if (v == "0" || v.isEmpty) None else Some(CacheParams(capacityBytes = int(k, v, 1) * 1024)))
      case "--ids"    => a = a.copy(numRayIds = int(k, v, 2))
      case "--stack"  => a = a.copy(stackDepth = if (v.isEmpty) None else Some(int(k, v, 1)))
      case "--rays"   => a = a.copy(maxRays = if (v.isEmpty) None else Some(int(k, v, 1)))
      case "--bridge" => a = a.copy(bridge = Paths.get(v))
      case "--waves"  => a = a.copy(waves = flag(k, v))
      case "--strict" => a = a.copy(strict = flag(k, v))
      case "--size"   => a = a.copy(sized = flag(k, v))
      case "--sim" => a = a.copy(sim = v match {
          case "chiseltest" | "cpp" | "" => if (v.isEmpty) "chiseltest" else v
          case _                         => fail(s"$k: '$v' (chiseltest or cpp)")
        })
      case "--seed" => a = a.copy(seed = v.toLongOption.getOrElse(fail(s"--seed: '$v'")))
      case other    => fail(s"unknown option '$other'")
    }
    if (a.memoryKind == MemoryKind.OnChip) {
      if (a.memLatency.isDefined)
        fail(s"--mem-latency ${a.memLatency.get.describe}: with --memory onchip the latency is fixed at " +
          s"${MemoryKind.OnChip.LatencyCycles} cycles (the option applies to --memory ddr)")
      if (a.cache.isDefined)
        fail("--cache: with --memory onchip there is no cache (on-chip memory; the option applies to --memory ddr)")
    }
    a
  }

  private def wrap[A](k: String)(f: => A): A =
    try f
    catch { case e: IllegalArgumentException => fail(s"$k: ${e.getMessage}") }

  private def fail(why: String): Nothing = throw new IllegalArgumentException(s"$why\n$usage")
}
