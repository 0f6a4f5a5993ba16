package rtaccel.regress

import rtaccel.AccelConfig
import rtaccel.sim.RunResult

/** The regression's numbers: stats.json (the simulation), report.json (stats
  * plus nori-bridge's accuracy), report.md and a console table.
  */
object Report {

  /** The throughput bound of a run, from what the hardware is and what the
    * run asked of it: each term is a resource's capacity per cycle over the
    * run's use of it per ray, and the smallest term is the bound.
    *  - `boxLanes`: BboxIntersect takes one node (all its child boxes at once)
    *    per cycle; `boxTests` counts node tests.
    *  - `triangleLanes`: PrimIntersect takes one triangle test per cycle.
    *  - `control`: TraversalControl makes one decision per cycle in each of
    *    its two lanes: box results (`decisions - leafReturns`) and leaf
    *    returns (`leafReturns`); the busier lane sets the term.
    *  - `dram` (DDR only): the DRAM's peak bytes per cycle at the fabric clock
    *    over the bytes per ray it moved, whole bursts, both ports.
    * Model parameters chosen to suit the design (a port's record size, the
    * outstanding limit) are not terms.
    */
  final case class Bound(terms: Seq[(String, Double)]) {
    val (limitedBy, raysPerCycle) = terms.minBy(_._2)
    def toJson: ujson.Obj = ujson.Obj.from(terms.map { case (k, v) => k -> ujson.Num(v) })
  }
  object Bound {
    val Terms: Seq[String] = Seq("boxLanes", "triangleLanes", "control", "dram")
    def apply(rays: Int, perf: Map[String, BigInt], dram: Option[rtaccel.sim.mem.DramStats], dramBytes: Long): Bound = {
      def perRay(x: Double) = (x / rays.max(1)).max(1e-9) // a resource a run never used bounds nothing
      Bound(Seq(
        "boxLanes" -> 1.0 / perRay(perf("boxTests").toDouble),
        "triangleLanes" -> 1.0 / perRay(perf("triTests").toDouble),
        "control" -> 1.0 / perRay((perf("decisions") - perf("leafReturns")).toDouble max perf("leafReturns").toDouble)
      ) ++
        dram.map(d => "dram" -> d.bytesPerCycle / perRay(dramBytes.toDouble)))
    }
  }

  def stats(
      a: RegressArgs,
      cfg: AccelConfig,
      datapath: String,
      rays: Int,
      r: RunResult,
      simSeconds: Double,
      wallSeconds: Double,
      goldenMismatches: Int,
      errorRays: Int
  ): ujson.Obj = {
    val p = r.perf.map { case (k, v) => k -> v.toDouble }
    def perRay(k: String) = p(k) / rays.max(1)
    // Every byte the DRAM moved: nodes and triangles, and in the system (SIM=cpp) also
    // the rays read and hits written through it, which load the same DRAM.
    val dramBytes = r.dram.fold(r.node.dramBytes + r.tri.dramBytes)(_.bytes)
    val bound = Bound(rays, r.perf, r.dram, dramBytes)
    ujson.Obj(
      "rays" -> rays,
      "cycles" -> r.cycles.toDouble,
      "raysPerCycle" -> rays / r.cycles.toDouble,
      "boundRaysPerCycle" -> bound.raysPerCycle,
      "boundLimitedBy" -> bound.limitedBy,
      "boundTerms" -> bound.toJson,
      "efficiency" -> (rays / r.cycles.toDouble) / bound.raysPerCycle,
      "dramBytesPerRay" -> r.dram.fold[ujson.Value](ujson.Null)(_ => ujson.Num(dramBytes.toDouble / rays.max(1))),
      "nodeTestsPerRay" -> perRay("boxTests"),
      "nodeBytesPerRay" -> r.node.portBytes.toDouble / rays.max(1),
      "triangleTestsPerRay" -> perRay("triTests"),
      "decisionsPerRay" -> perRay("decisions"),
      "meanRaysInFlight" -> p("inFlightSum") / r.cycles.toDouble,
      "steady" -> steady(r),
      "goldenMismatches" -> goldenMismatches,
      "errorRays" -> errorRays,
      "memory" -> ujson.Obj(
        "kind" -> a.memoryKind.name,
        "node" -> ujson.read(r.node.toJson),
        "triangle" -> ujson.read(r.tri.toJson),
        "dramBytes" -> dramBytes.toDouble,
        "dram" -> r.dram.fold[ujson.Value](ujson.Null)(_.toJson)
      ),
      "counters" -> ujson.Obj.from(p.toSeq.sortBy(_._1).map { case (k, v) => k -> ujson.Num(v) }),
      "simulation" -> ujson.Obj(
        "seconds" -> simSeconds,
        "cyclesPerSecond" -> r.cycles / simSeconds.max(1e-9),
        "wallSeconds" -> wallSeconds
      ),
      "configuration" -> configuration(a, cfg, datapath)
    )
  }

  /** stats.json's `configuration`: the hardware and the memory settings of a run. */
  def configuration(a: RegressArgs, cfg: AccelConfig, datapath: String): ujson.Obj = ujson.Obj(
    "datapath" -> datapath,
    "float" -> cfg.floatName,
    "triangle" -> a.triangle,
    "rounding" -> a.rounding,
    "numRayIds" -> cfg.numRayIds,
    "stackDepth" -> cfg.stackDepth,
    "nodeIndexBits" -> cfg.nodeIndexBits,
    "triIndexBits" -> cfg.triIndexBits,
    "maxLeafSize" -> cfg.maxLeafSize,
    "memory" -> a.describeMemory,
    "fabricMhz" -> a.fabricMhz,
    "seed" -> a.seed.toDouble
  )

  private val classes = Seq(
    "false_miss" -> "falseMiss",
    "false_hit" -> "falseHit",
    "wrong_prim" -> "wrongPrim",
    "t_error" -> "tOutOfTolerance",
    "tie" -> "ties",
    "edge" -> "edgeCases",
    "reference_wrong" -> "referenceWrong",
    "agree" -> "agree"
  )

  def combine(stats: ujson.Obj, accuracy: ujson.Value): ujson.Obj = {
    val counts =
      accuracy.obj.get("counts").map(_.obj).getOrElse(collection.mutable.LinkedHashMap.empty[String, ujson.Value])
    val mismatches = ujson.Obj.from(classes.map { case (k, name) => name -> counts.getOrElse(k, ujson.Num(0)) })
    mismatches("total") = accuracy.obj.get("mismatches").getOrElse(ujson.Num(0))
    val out = ujson.Obj.from(stats.obj)
    out("mismatches") = mismatches
    out("accuracy") = accuracy
    out
  }

  /** The run's middle (RunResult.window): the rays answered between its snapshots over the cycles between, and
    * the bound of the same terms over the counters' growth in that window. A term's share is its resource's busy
    * share there (the bound is linear in the rays), so `efficiency` is how busy the limiting resource was once
    * the pipelines had filled and before the batch drained. Null when the run has no window.
    */
  def steady(r: RunResult): ujson.Value = r.window.fold[ujson.Value](ujson.Null) { case (a, b) =>
    val (rays, cycles) = (b.hits - a.hits, (b.cycle - a.cycle).max(1L))
    val perf = b.perf.map { case (k, v) => k -> (v - a.perf.getOrElse(k, BigInt(0))) }
    val dram = for (x <- a.dram; y <- b.dram)
      yield rtaccel.sim.mem.DramStats(cycles, y.bytes - x.bytes, y.bytesPerCycle, y.burstBytes, y.busyCycles - x.busyCycles)
    val bound = Bound(rays, perf, dram, dram.fold(0L)(_.bytes))
    ujson.Obj(
      "fromShare" -> rtaccel.sim.RunResult.WindowFrom,
      "toShare" -> rtaccel.sim.RunResult.WindowTo,
      "rays" -> rays,
      "cycles" -> cycles.toDouble,
      "raysPerCycle" -> rays / cycles.toDouble,
      "boundRaysPerCycle" -> bound.raysPerCycle,
      "boundLimitedBy" -> bound.limitedBy,
      "efficiency" -> (rays / cycles.toDouble) / bound.raysPerCycle
    )
  }

  private def n(v: ujson.Value, digits: Int = 4): String = v match {
    case ujson.Num(x) if x == x.round.toDouble && math.abs(x) < 1e15 => f"${x.toLong}%,d"
    case ujson.Num(x)                                                => s"%.${digits}f".format(x)
    case other                                                       => other.toString
  }

  def table(r: ujson.Obj): String = {
    val m = r("mismatches").obj
    Seq(
      "rays" -> n(r("rays")),
      "cycles" -> n(r("cycles")),
      "rays/cycle" -> s"${n(r("raysPerCycle"))} (bound ${n(r("boundRaysPerCycle"))}, ${n(r("efficiency"), 2)} of it; limited by ${r("boundLimitedBy").str})",
      "bound terms (rays/cycle)" -> r("boundTerms").obj.map { case (k, v) => s"$k ${n(v)}" }.mkString(", "),
      "DRAM bytes per ray" -> (r("dramBytesPerRay") match {
        case ujson.Null => "- (on chip)"
        case v =>
          val Seq(node, tri) = Seq("node", "triangle").map(k => r("memory")(k)("dramBytes").num / r("rays").num)
          val other = v.num - node - tri // the system's rays and hits
          s"${n(v, 1)} (node ${n(node, 1)}, triangle ${n(tri, 1)}" + (if (other > 0.05)
                                                                        s", rays and hits ${n(other, 1)}"
                                                                      else "") +
            s"; DRAM busy ${n(r("memory")("dram")("busyShare"), 2)})"
      }),
      "node / triangle tests per ray" -> s"${n(r("nodeTestsPerRay"), 2)} / ${n(r("triangleTestsPerRay"), 2)}",
      "node bytes per ray" -> n(r("nodeBytesPerRay"), 1),
      "mean rays in flight" -> n(r("meanRaysInFlight"), 1),
      "steady state" -> (r.obj.get("steady") match {
        case Some(w: ujson.Obj) =>
          f"${n(w("raysPerCycle"))} rays/cycle, ${n(w("efficiency"), 2)} of its bound (${w("boundLimitedBy").str}" +
            f"; answers ${100 * w("fromShare").num}%.0f-${100 * w("toShare").num}%.0f %%, ${n(w("cycles"))} cycles)"
        case _ => "- (no window: SIM=cpp or too few rays)"
      }),
      "golden mismatches" -> n(r("goldenMismatches")),
      "vs Embree" -> s"${n(m("total"))} mismatches (false miss ${n(m("falseMiss"))}, false hit ${n(m("falseHit"))}, wrong prim ${n(
          m("wrongPrim")
        )}, t ${n(m("tOutOfTolerance"))}); ties ${n(m("ties"))}, edge ${n(m("edgeCases"))}, reference wrong ${n(m("referenceWrong"))}",
      "rays with errors" -> n(r("errorRays")),
      "simulator" -> s"${n(r("simulation")("cyclesPerSecond"), 0)} cycles/s, ${n(r("simulation")("wallSeconds"), 1)} s"
    ).map { case (k, v) => f"  $k%-30s $v" }.mkString("\n")
  }

  def markdown(r: ujson.Obj): String = {
    val cfg = r("configuration").obj.map { case (k, v) =>
      s"| $k | ${v match { case ujson.Str(s) => s; case o => n(o) }} |"
    }
    // Built line by line: stripMargin would eat the leading `|` of interpolated rows.
    (Seq(
      "# Regression report",
      "",
      "Generated by `make regress`; do not edit.",
      "",
      "```",
      table(r),
      "```",
      "",
      "| configuration | value |",
      "| --- | --- |"
    ) ++ cfg ++ Seq("")).mkString("\n")
  }
}
