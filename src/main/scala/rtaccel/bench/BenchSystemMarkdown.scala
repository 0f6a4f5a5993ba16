package rtaccel.bench

/** The system section of docs/reports/performance.md: rays/cycle per core count, the
  * ZC706 estimate beside Embree on this machine, and the throughput goals, each
  * met or not and, if not, the term (cores, rays/cycle, clock) that holds it
  * back, with the numbers.
  */
object BenchSystemMarkdown {

  /** RayCore Lite's measured Cornell figure (Arria 10), the first throughput goal. */
  val CornellGoalMrays = 160.0

  /** The second throughput goal: dragon primary at least this many times Embree on this machine. */
  val DragonTimesEmbree = 5.0

  /** The clock the per-core table's DDR model and the MIG's AXI side assume (FABRIC_MHZ's default):
    * the ceiling the clock term is measured against. An assumption, not a timing result. */
  val ClockCeilingMhz = 200.0

  /** m_axi moves one beat per cycle, of its width (a row's `axiDataBits`; rows cached before it was recorded: 512 bits,
    * 64 bytes): the DRAM can never give the system more per cycle. */
  def beatBytes(row: ujson.Value): Double = row.obj.get("axiDataBits").fold(64.0)(_.num / 8)
  val DdrBytesPerSecond = 12.8e9

  private def f(x: Double, d: Int) = s"%.${d}f".format(x)

  def apply(r: BenchSystem.Result, maxRays: Int): String = {
    val v = r.estimateFigures
    val fit = v.coresFit
    val mhz = r.estimateMhz.toDouble
    val simMhz = r.fabricMhz.toDouble
    val cores = r.rows.map(_("cores").num.toInt).distinct.sorted
    val runs = Bench.Runs.map(_.name).filter(n => r.rows.exists(_("run").str == n))
    def row(run: String, n: Int) = r.rows.find(x => x("run").str == run && x("cores").num.toInt == n).get
    def rpc(run: String, n: Int) = row(run, n)("raysPerCycle").num

    /** estimate, not run on a board: the fitting system's rays/cycle x the Fmax estimate (MHz -> Mrays/s). */
    def estimate(run: String) = rpc(run, fit) * mhz
    val store = rtaccel.system.SystemConfig() // the stores' sizes the bench's systems are built with (the defaults)
    val header = Seq(
      "",
      "## The system on a ZC706 (estimate, not run on a board) against Embree (this machine)",
      "",
      s"Simulated by `make bench` at commit ${r.sim.commit} (${r.sim.at}). The system top `rtaccel_system` (N cores, the MemoryFabric with its node",
      s"store and triangle store (the first ${store.nodeStoreBytes / 1024} KiB of nodes, ${store.triStoreBytes / 1024} KiB of triangles on chip: docs/scene-store.md), ray and hit DMA through DDR, registers), ${coresNote(r)} FP32 watertight cores (conservative boxes, ${BenchMarkdown.idsNote(
          r.rows.map(_.obj.get("rayIds"))
        )}each),",
      "under the C++ harness (`sw/sim/`, driven by librtaccel as on the board) with the ZC706 DDR model behind `m_axi`:",
      "12.8 GB/s, 64-byte bursts, 100 ns latency, 64 outstanding, out of order, clocked at the accelerator's estimated",
      s"clock, ${f(simMhz, 0)} MHz (${f(DdrBytesPerSecond / (simMhz * 1e6), 0)} B/cycle, at most one ${r.rows.map(
          beatBytes
        ).distinct.map(f(_, 0)).mkString("/")}-byte beat per cycle on `m_axi`).",
      s"Cycles are the CYCLES register (START to DONE). Each run simulates at most $maxRays rays, strided over the set,",
      "every one checked bit for bit against the golden model.",
      "",
      s"From `make verilog` (`build/verilog/resources.md`, ${v.title}): **$fit cores fit** on the xc7z045, and the",
      s"**Fmax estimate is ${f(v.fmaxMhz, 1)} MHz** (slowest unit ${v.slowestUnit}; the longest path by a delay model over Yosys's netlist, `docs/fmax.md`).",
      s"The estimate uses ${f(mhz, 0)} MHz: the Fmax estimate rounded down, and at most the MIG's ${f(ClockCeilingMhz, 0)} MHz user clock, which the system runs on."
    ) ++ redrawn(r) ++ Seq(
      "",
      s"| rays | simulated | ${cores.map(n => s"$n ${if (n == 1) "core" else "cores"}${if (n == fit) " (fit)" else ""}").mkString(
          " | "
        )} | node store hit rate ($fit) | DRAM bytes/ray ($fit) | m_axi R bytes/ray ($fit) | m_axi R beats/cycle ($fit; max 1) | golden mismatches |",
      s"| --- | ---: | ${cores.map(_ => "---:").mkString(" | ")} | ---: | ---: | ---: | ---: | ---: |"
    )
    val table = runs.map { run =>
      val x = row(run, fit)
      s"| $run | ${x("rays").num.toInt} of ${x("raySetSize").num.toInt} | ${cores.map(n => f(rpc(run, n), 4)).mkString(" | ")} | " +
        s"${f(100 * x("nodeStoreHitRate").num, 1)}% | ${f(x("dramBytesPerRay").num, 0)} | ${f(x("readBytesPerRay").num, 0)} | " +
        s"${f(x("readBeatsPerCycle").num, 2)} | " +
        s"${cores.map(n => row(run, n)("goldenMismatches").num.toInt).sum} |"
    }
    val answer = Seq(
      "",
      "rays/cycle: of the whole system (all its cores).",
      "",
      "Embree: `nori-bridge bench` on the whole ray set, the best of 3 tries, wall clock on 2 threads of this shared",
      "2-core machine. The 1-minute load average just before the chosen try says how busy the machine was with",
      "other work (2 = both cores taken): above about 0.5, Embree is understated and the ratio overstated.",
      s"`make bench-embree${BenchSystem.makeVars(r.layout, r.boxTest)}` re-measures only Embree and redraws this section from " +
        s"`${Bench.root.resolve(BenchSystem.cacheName(r.layout, r.boxTest))}`.",
      "",
      s"| rays | ZC706, estimate, not run on a board: Mrays/s = rays/cycle of the $fit-core system × ${f(mhz, 0)} MHz | Embree, this machine: Mrays/s (2 threads, packets of 8) | load average (1 min) at Embree's try | Embree measured (UTC) | ZC706 estimate / Embree |",
      "| --- | ---: | ---: | ---: | --- | ---: |"
    ) ++ runs.map { run =>
      val e = r.embree(run)
      s"| $run | ${f(estimate(run), 1)} (= $fit × ${f(rpc(run, fit) / fit, 4)} rays/cycle per core × ${f(mhz, 0)} MHz) | ${f(e.packetsMrays, 1)} | " +
        s"${if (e.load1.isNaN) "unknown" else f(e.load1, 2)} | ${e.at} | ${f(estimate(run) / e.packetsMrays, 2)} |"
    }
    // Embree's host beside its figures: these shared VMs differ up to 2x from one host to the next.
    val hosts = runs.groupBy(run => r.embree(run).host).toSeq.sortBy(_._2.map(runs.indexOf).min).map { case (h, rs) =>
      s"- Embree's host${if (rs.size == runs.size) "" else s" for ${rs.mkString(", ")}"} (`/proc/cpuinfo`): $h"
    }
    val traffic = Seq(
      "",
      "**DRAM traffic per ray set and core count** (the DDR model's count in the batch, every burst whole:",
      "reads and writes by the image region they touched; R channel busy = m_axi's R beats per cycle, at most one;",
      "DDR busy = the share of cycles the DDR model's channel was moving data):",
      "",
      "| rays | cores | rays/cycle | DRAM bytes/ray | nodes | triangles | rays | hits | m_axi R bytes/ray | R channel busy | DDR busy |",
      "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    ) ++
      (for (run <- runs; n <- cores) yield {
        val x = row(run, n)
        def region(k: String) = x.obj.get("dramRegionBytesPerRay").flatMap(_.obj.get(k)).fold("–")(v => f(v.num, 0))
        s"| $run | $n | ${f(rpc(run, n), 4)} | ${f(x("dramBytesPerRay").num, 0)} | ${region("nodes")} | ${region("triangles")} | " +
          s"${region("rays")} | ${region("hits")} | ${f(x("readBytesPerRay").num, 0)} | ${f(x("readBeatsPerCycle").num, 2)} | " +
          s"${x.obj.get("dramBusy").fold("–")(v => f(v.num, 2))} |"
      })
    val goals = Seq("", "**Throughput goals** (the estimate, not run on a board):", "") ++
      runs.find(_ == "cornell-box-primary").map(run =>
        goal(
          s"Cornell primary ≥ ${f(CornellGoalMrays, 0)} Mrays/s (RayCore Lite, measured on an Arria 10)",
          run,
          CornellGoalMrays,
          r
        )
      ).toSeq ++
      runs.find(_ == "dragon-primary").map { run =>
        val e = r.embree(run).packetsMrays
        goal(
          s"Dragon primary ≥ ${f(DragonTimesEmbree, 0)}× Embree on this machine (${f(e, 1)} Mrays/s, so ≥ ${f(DragonTimesEmbree * e, 1)})",
          run,
          DragonTimesEmbree * e,
          r
        )
      }.toSeq
    (header ++ table ++ answer ++ hosts ++ traffic ++ goals).mkString("\n")
  }

  /** Where the estimate's cores and Fmax differ from those the rays/cycle were simulated with: say which came from where. */
  /** The cores' node layout and box test, as the page's first paragraph names them ("4-wide" by default). */
  def coresNote(r: BenchSystem.Result): String = {
    val grid = r.boxTest == rtaccel.BoxTest.Grid.name
    rtaccel.bvh.BvhLayout.parse(r.layout) match {
      case w: rtaccel.bvh.BvhLayout.Wide if w.quantized =>
        s"${w.name} (quantized ${w.k}-wide nodes of ${w.nodeBytes} bytes" +
          (if (grid) ", child boxes tested in the node's grid: docs/kernels.md)" else ")")
      case w: rtaccel.bvh.BvhLayout.Wide => s"${w.k}-wide"
      case _                             => r.layout
    }
  }

  private def redrawn(r: BenchSystem.Result): Seq[String] = r.now.toSeq.flatMap { case (_, p) =>
    val sim = r.verilog
    Seq(
      "",
      s"**Redrawn from the cache** (`make bench BENCH_SYSTEM=cached` or `make bench-embree`): the rays/cycle below were",
      s"simulated at commit ${r.sim.commit} (${r.sim.at}) with the DDR model clocked at ${r.fabricMhz} MHz, when `make verilog` said",
      s"${sim.coresFit} cores fit and ${f(sim.fmaxMhz, 1)} MHz (${sim.slowestUnit}). The cores that fit and the Fmax estimate above are",
      s"`build/verilog/resources.md` as written at ${p.at} (read at commit ${p.commit})."
    ) ++ (if (r.estimateMhz == r.fabricMhz)
            Seq(s"The estimate's clock is the one simulated, ${r.fabricMhz} MHz.")
          else
            Seq(
              s"The rays/cycle were not re-simulated at ${r.estimateMhz} MHz: at a faster clock the DDR's 100 ns are more cycles and its 12.8 GB/s fewer bytes",
              "per cycle, so where the DRAM binds, the estimate below may be optimistic; `make bench` measures it."
            ))
  }

  /** One goal: met or not; if not, each term's headroom against its ceiling and the one that holds the estimate back. */
  def goal(what: String, run: String, target: Double, r: BenchSystem.Result): String = {
    val fit = r.estimateFigures.coresFit
    val mhz = r.estimateMhz.toDouble
    val x = r.rows.find(y => y("run").str == run && y("cores").num.toInt == fit).get
    val sysRpc = x("raysPerCycle").num
    val est = sysRpc * mhz
    if (est >= target) return s"- $what: **met**, ${f(est, 1)} Mrays/s."
    val need = target / est
    // Ceilings: the clock at ClockCeilingMhz; cores at what fits (area); rays/cycle at the memory bound of the fitting
    // system at this clock: the least of m_axi's R channel (one beat of its width per cycle over its read bytes per ray)
    // and the DDR (12.8 GB/s in bytes per cycle over its DRAM bytes per ray, reads and writes in whole bursts).
    def over(bytesPerCycle: Double, perRay: Double) =
      if (perRay > 0) bytesPerCycle / perRay else Double.PositiveInfinity
    val dramBound = math.min(
      over(beatBytes(x), x("readBytesPerRay").num),
      over(DdrBytesPerSecond / (mhz * 1e6), x("dramBytesPerRay").num)
    )
    val terms = Seq(
      (
        "clock",
        ClockCeilingMhz / mhz,
        s"${f(mhz, 0)} MHz now; the goal needs ${f(mhz * need, 0)} MHz at these cores and rays/cycle (ceiling taken as ${f(ClockCeilingMhz, 0)} MHz, the fabric clock the DDR model and the MIG's AXI side assume)"
      ),
      (
        "rays/cycle",
        dramBound / sysRpc,
        s"${f(sysRpc, 4)} per system now (${f(sysRpc / fit, 4)} per core); the goal needs ${f(sysRpc * need, 4)}; the memory bound at this clock is ${if (dramBound.isInfinite) "none (no DRAM traffic)"
          else f(dramBound, 4)} (m_axi R: ${f(x("readBytesPerRay").num, 0)} bytes/ray at ${f(x("readBeatsPerCycle").num, 2)} beats/cycle now; DDR: ${f(x("dramBytesPerRay").num, 0)} bytes/ray)"
      ),
      (
        "cores",
        1.0,
        s"$fit fit now (area, `make verilog`); the goal needs ${f(fit * need, 1)} at this rays/cycle per core and clock"
      )
    )
    val (worst, headroom, _) = terms.maxBy(_._2)
    val alone = if (headroom >= need) s"raising it to its ceiling alone would meet the goal"
    else
      s"even at its ceiling (×${f(headroom, 2)}) it falls short of the ×${f(need, 2)} needed, so more than one term must move"
    (Seq(
      s"- $what: **not met**, ${f(est, 1)} Mrays/s (×${f(need, 2)} short). Held back most by the **$worst** ($alone):"
    ) ++
      terms.map { case (n, h, s) => s"  - $n: $s (headroom ×${if (h.isInfinite) "∞" else f(h, 2)})" }).mkString("\n")
  }
}
