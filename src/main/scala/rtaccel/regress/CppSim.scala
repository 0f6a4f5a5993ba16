package rtaccel.regress

import chisel3.Data
import rtaccel.golden.HitRecord
import rtaccel.system.{RtAccelSystem, SystemConfig}
import rtaccel.tools.Synth
import rtaccel.{AccelConfig, Datapath, ErrorFlags}
import rtaccel.sim.RunResult
import rtaccel.sim.mem.{DramStats, MemStats, MemoryKind}

import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.nio.file.{Files, Path, Paths}
import scala.sys.process._

/** `make regress SIM=cpp`: the system top (rtaccel_system, one core) under a
  * C++ Verilator harness with no JVM in the loop (sw/sim/, driven by
  * librtaccel as a program on the board would be). The JVM only emits the
  * Verilog, starts `rtaccel-sim`, and reads back what it wrote: the hit
  * records as the hardware wrote them into DDR (hits.bin) and the counters
  * and DDR statistics (sim.json, sim-memory.json); the report is then made
  * by the same code as the chiseltest path's.
  */
object CppSim {

  /** Where the simulator of a configuration is built (make reuses an unchanged build): one directory per
    * datapath, cores, ray IDs, stack depth and node layout. */
  def simDir(dp: String, cfg: AccelConfig, cores: Int, axiDataBits: Int = SystemConfig.defaultAxiDataBits): Path =
    Paths.get(
      "build",
      "cppsim",
      s"system_${dp}_c${cores}_n${cfg.numRayIds}_d${cfg.stackDepth}_k${cfg.boxLanes}" +
        // 4q nodes have the 4-wide's lanes but another decode: their own build, not the 4-wide one rebuilt.
        (if (cfg.layout.quantized) "q" else "") +
        // Grid box tests: another box unit, its own build too.
        (if (cfg.gridBox) "g" else "") +
        (if (axiDataBits == 512) "" else s"_w$axiDataBits")
    ).toAbsolutePath

  /** make cppsim-test's build, under a name that does not spell its configuration: `make render RTL=1` and
    * the Nori drop-in's rtl mode (mk/render.mk, scripts/render.sh) link against it, so the configuration
    * is named once, by the package cppsim-test runs on.
    */
  val TestSystemLink: Path = Paths.get("build", "cppsim", "test-system").toAbsolutePath

  /** Points [[TestSystemLink]] at `dir` (a sibling, so the link is relative and survives a moved checkout). */
  def linkTestSystem(dir: Path): Unit = {
    Files.deleteIfExists(TestSystemLink)
    Files.createSymbolicLink(TestSystemLink, TestSystemLink.getParent.relativize(dir))
  }

  /** Emits rtaccel_system for `cfg` and builds rtaccel-sim and test-librtaccel beside it (sw/Makefile).
    * With `clang` the model and the harness are compiled by clang (sw/Makefile CXX=clang++; Debian's clang
    * installed on first use) in their own directory (`simDir` + `_clang`), so the gcc build that
    * `make cppsim-test` makes stays as it is, from SystemVerilog lowered for Verilator ([[ClangModelFirtoolOpts]]).
    * clang's model executes 10.6% fewer instructions per simulated cycle than gcc's build and 5.3% fewer than
    * gcc's profile-guided one, and builds in less time (docs/cppsim.md "Speed").
    */
  def build[T <: Data](
      cfg: AccelConfig,
      dp: Datapath[T],
      cores: Int = 1,
      clang: Boolean = false,
      axiDataBits: Int = SystemConfig.defaultAxiDataBits
  ): Path = {
    val plain = simDir(dp.name, cfg, cores, axiDataBits)
    val dir = if (clang) plain.resolveSibling(plain.getFileName.toString + "_clang") else plain
    Files.createDirectories(dir)
    def gen =
      new RtAccelSystem(
        SystemConfig(core = cfg, cores = cores, axiDataBits = axiDataBits),
        dp
      ) // by name: elaborated inside the emitter
    val sv = if (clang) circt.stage.ChiselStage.emitSystemVerilog(gen, firtoolOpts = ClangModelFirtoolOpts)
    else Synth.emit(gen)
    val svPath = dir.resolve("rtaccel_system.sv")
    // Rewritten only when it changed, so make keeps a build of the same hardware.
    if (!Files.exists(svPath) || Files.readString(svPath) != sv) Files.writeString(svPath, sv)
    val cxx = if (clang) Seq("CXX=clang++") else Nil
    println(s"cppsim: building the simulator in $dir (Verilator; a few minutes the first time" +
      (if (clang) ", clang; CPPSIM_CLANG=0 for the gcc build make cppsim-test makes)" else ")"))
    val rc = (Seq("make", "-s", "-C", "sw", "sim", s"SIMDIR=$dir", s"VSRC=$svPath") ++ cxx).!
    if (rc != 0)
      throw new IllegalStateException(s"cppsim: building the simulator in $dir failed (make -C sw sim, exit $rc)")
    dir
  }

  /** firtool's options for the clang build's SystemVerilog: the same FIRRTL as every other emission, lowered
    * with packed arrays and local variables (firtool's defaults; Yosys needs them disallowed, Verilator does
    * not): clang's model then executes 2.4% fewer instructions per simulated cycle (gcc's 6.5% more, so the gcc
    * build keeps [[Synth.emit]]'s lowering; docs/cppsim.md "Speed").
    */
  val ClangModelFirtoolOpts: Array[String] = Array("-disable-all-randomization", "-strip-debug-info")

  /** Whether `make regress SIM=cpp` and `make cppsim-compare` use the clang build: yes unless CPPSIM_CLANG=0
    * (make passes a command-line variable on in the environment), which makes them use the gcc build
    * `make cppsim-test` made (no second model build; `make demo` does so).
    */
  def useClang: Boolean = !sys.env.get("CPPSIM_CLANG").contains("0")

  /** Hit records as the hardware writes them (system contract): 32 bytes, ray order. */
  def readHits(path: Path, rays: Int): IndexedSeq[HitRecord] = {
    val bytes = Files.readAllBytes(path)
    if (bytes.length != 32 * rays)
      throw new IllegalArgumentException(s"$path: ${bytes.length} bytes, expected $rays hit records of 32 bytes")
    val b = ByteBuffer.wrap(bytes).order(ByteOrder.LITTLE_ENDIAN)
    def u32(off: Int) = b.getInt(off).toLong & 0xffffffffL
    (0 until rays).map { i =>
      val o = 32 * i
      val status = u32(o + 4)
      HitRecord(
        u32(o),
        (status & 1) == 1,
        u32(o + 8),
        u32(o + 12),
        u32(o + 16),
        u32(o + 20),
        ((status >> 8) & ((1 << ErrorFlags.width) - 1)).toInt
      )
    }
  }

  /** The rtaccel-sim options that carry `a`'s memory settings; refuses what the system has not got. */
  def memoryOptions(a: RegressArgs): Seq[String] = {
    if (a.memoryKind == MemoryKind.OnChip)
      throw new IllegalArgumentException(
        "SIM=cpp: MEMORY=onchip: the system top reads DDR through m_axi (use MEMORY=ddr)"
      )
    if (a.cache.isDefined)
      throw new IllegalArgumentException(
        "SIM=cpp: CACHE=: the system has its own node store; the DDR model has no cache"
      )
    val lat = a.memLatency.getOrElse(MemoryKind.Ddr.DefaultLatency)
    Seq(
      "--mem-latency",
      s"${lat.lo}-${lat.hi}",
      "--fabric-mhz",
      a.fabricMhz.toString,
      "--outstanding",
      a.outstanding.toString,
      "--seed",
      a.seed.toString
    )
  }

  /** Runs `rays` (the package's first `rays`) through rtaccel-sim; returns the run and the simulation's speed. */
  def run(a: RegressArgs, dir: Path, nodeBytes: Int, rays: Int): (RunResult, ujson.Obj) = {
    val out = a.out.toAbsolutePath
    val cmd = Seq(
      dir.resolve("rtaccel-sim").toString,
      "--package",
      a.pkg.toAbsolutePath.toString,
      "--out",
      out.toString,
      "--rays",
      rays.toString
    ) ++ memoryOptions(a) ++ (if (a.waves) Seq("--vcd", out.resolve("waves.vcd").toString) else Nil)
    println(s"cppsim: ${cmd.mkString(" ")}")
    // rtaccel-sim's progress lines (stderr, "rtaccel sim: ...") to stdout: sbt tags a forked JVM's stderr "[error]".
    val rc = cmd.!(scala.sys.process.ProcessLogger(
      println(_),
      l => if (l.startsWith("rtaccel sim: ")) println(l) else System.err.println(l)
    ))
    if (rc != 0) throw new IllegalStateException(s"cppsim: rtaccel-sim failed (exit $rc)")
    val sim = ujson.read(Files.readString(out.resolve("sim.json"))).obj
    val mem = ujson.read(Files.readString(out.resolve("sim-memory.json"))).obj
    val violations = mem("violations").arr
    if (violations.nonEmpty)
      throw new IllegalStateException(
        s"cppsim: AXI protocol violations by rtaccel_system:\n  ${violations.map(_.str).mkString("\n  ")}"
      )
    (result(sim, mem, out.resolve("hits.bin"), nodeBytes, rays), ujson.Obj.from(sim("simulation").obj))
  }

  /** The run in the chiseltest path's terms. The system's memory is one AXI port,
    * so the per-port statistics are the hardware's fetch counters and the bytes
    * of bursts that fell in the node and triangle arrays; cache and per-port
    * stall fields do not apply (0).
    */
  def result(
      sim: collection.Map[String, ujson.Value],
      mem: collection.Map[String, ujson.Value],
      hits: Path,
      nodeBytes: Int,
      rays: Int
  ): RunResult = {
    val counters = sim("counters").obj
    val cycles = counters("cycles").num.toLong
    val perf = counters.map { case (k, v) => k -> BigInt(v.num.toLong) }.toMap
    def regionRead(name: String) = mem("regions").obj.get(name).fold(0L)(_("readBytes").num.toLong)
    def port(name: String, recordBytes: Int, fetches: Long, dramBytes: Long) =
      MemStats(name, cycles, recordBytes, fetches, fetches, dramBytes, 0, 0, 0, 0, 0, 0, 0, 0)
    val d = mem("dram").obj
    RunResult(
      readHits(hits, rays),
      cycles,
      perf,
      port("node", nodeBytes, counters("nodeFetches").num.toLong, regionRead("nodes")),
      port(
        "triangle",
        rtaccel.leaf.TriangleRecord.RecordBytes,
        counters("triFetches").num.toLong,
        regionRead("triangles")
      ),
      Some(DramStats(
        cycles,
        d("bytes").num.toLong,
        d("bytesPerCycle").num,
        d("burstBytes").num.toInt,
        d("busyCycles").num.toLong
      ))
    )
  }
}
