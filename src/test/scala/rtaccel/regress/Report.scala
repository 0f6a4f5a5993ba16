package rtaccel.regress

import rtaccel.AccelConfig
import rtaccel.system.RunResult

/** The regression's numbers: stats.json (the simulation), report.json (stats
  * plus nori-bridge's accuracy), report.md and a console table.
  */
object Report {
  def stats(a: RegressArgs, cfg: AccelConfig, datapath: String, rays: Int, r: RunResult, simSeconds: Double,
      wallSeconds: Double, goldenMismatches: Int, errorRays: Int): ujson.Obj = {
    val p = r.perf.map { case (k, v) => k -> v.toDouble }
    def perRay(k: String) = p(k) / rays.max(1)
    // Each unit takes one item per cycle, so the busiest one bounds throughput.
    val busiest = Seq("boxTests" -> perRay("boxTests"), "triTests" -> perRay("triTests"), "decisions" -> perRay("decisions"),
      "nodeFetches" -> perRay("nodeFetches"), "triFetches" -> perRay("triFetches")).maxBy(_._2)
    // Each port has its own return channel of bytesPerCycle: the port moving
    // more bytes per ray bounds throughput by bandwidth.
    val portBounds = Seq("nodePortBandwidth" -> r.node.dramBytes, "trianglePortBandwidth" -> r.tri.dramBytes)
      .map { case (n, bytes) => n -> a.bytesPerCycle / (bytes.toDouble / rays.max(1)).max(1e-9) }
    val unitBound = "unit:" + busiest._1 -> 1.0 / busiest._2.max(1e-9)
    val (limiter, bound) = (unitBound +: portBounds).minBy(_._2)
    ujson.Obj(
      "rays" -> rays,
      "cycles" -> r.cycles.toDouble,
      "raysPerCycle" -> rays / r.cycles.toDouble,
      "boundRaysPerCycle" -> bound,
      "boundLimitedBy" -> limiter,
      "efficiency" -> (rays / r.cycles.toDouble) / bound,
      "nodeTestsPerRay" -> perRay("boxTests"),
      "triangleTestsPerRay" -> perRay("triTests"),
      "decisionsPerRay" -> perRay("decisions"),
      "meanRaysInFlight" -> p("inFlightSum") / r.cycles.toDouble,
      "goldenMismatches" -> goldenMismatches,
      "errorRays" -> errorRays,
      "memory" -> ujson.Obj("node" -> ujson.read(r.node.toJson), "triangle" -> ujson.read(r.tri.toJson),
        "bytes" -> (r.node.dramBytes + r.tri.dramBytes).toDouble),
      "counters" -> ujson.Obj.from(p.toSeq.sortBy(_._1).map { case (k, v) => k -> ujson.Num(v) }),
      "simulation" -> ujson.Obj("seconds" -> simSeconds, "cyclesPerSecond" -> r.cycles / simSeconds.max(1e-9), "wallSeconds" -> wallSeconds),
      "configuration" -> ujson.Obj(
        "datapath" -> datapath, "float" -> cfg.float.name, "triangle" -> a.triangle, "rounding" -> a.rounding,
        "numRayIds" -> cfg.numRayIds, "stackDepth" -> cfg.stackDepth, "nodeIndexBits" -> cfg.nodeIndexBits,
        "triIndexBits" -> cfg.triIndexBits, "maxLeafSize" -> cfg.maxLeafSize,
        "memory" -> a.memory(0).describe, "seed" -> a.seed.toDouble)
    )
  }

  private val classes = Seq("false_miss" -> "falseMiss", "false_hit" -> "falseHit", "wrong_prim" -> "wrongPrim",
    "t_error" -> "tOutOfTolerance", "tie" -> "ties", "edge" -> "edgeCases", "reference_wrong" -> "referenceWrong", "agree" -> "agree")

  def combine(stats: ujson.Obj, accuracy: ujson.Value): ujson.Obj = {
    val counts = accuracy.obj.get("counts").map(_.obj).getOrElse(collection.mutable.LinkedHashMap.empty[String, ujson.Value])
    val mismatches = ujson.Obj.from(classes.map { case (k, name) => name -> counts.getOrElse(k, ujson.Num(0)) })
    mismatches("total") = accuracy.obj.get("mismatches").getOrElse(ujson.Num(0))
    val out = ujson.Obj.from(stats.obj)
    out("mismatches") = mismatches
    out("accuracy") = accuracy
    out
  }

  private def n(v: ujson.Value, digits: Int = 4): String = v match {
    case ujson.Num(x) if x == x.round.toDouble && math.abs(x) < 1e15 => f"${x.toLong}%,d"
    case ujson.Num(x) => s"%.${digits}f".format(x)
    case other => other.toString
  }

  def table(r: ujson.Obj): String = {
    val m = r("mismatches").obj
    Seq(
      "rays" -> n(r("rays")), "cycles" -> n(r("cycles")),
      "rays/cycle" -> s"${n(r("raysPerCycle"))} (bound ${n(r("boundRaysPerCycle"))}, ${n(r("efficiency"), 2)} of it; limited by ${r("boundLimitedBy").str})",
      "node / triangle tests per ray" -> s"${n(r("nodeTestsPerRay"), 2)} / ${n(r("triangleTestsPerRay"), 2)}",
      "mean rays in flight" -> n(r("meanRaysInFlight"), 1),
      "golden mismatches" -> n(r("goldenMismatches")),
      "vs Embree" -> s"${n(m("total"))} mismatches (false miss ${n(m("falseMiss"))}, false hit ${n(m("falseHit"))}, wrong prim ${n(m("wrongPrim"))}, t ${n(m("tOutOfTolerance"))}); ties ${n(m("ties"))}, edge ${n(m("edgeCases"))}, reference wrong ${n(m("referenceWrong"))}",
      "rays with errors" -> n(r("errorRays")),
      "simulator" -> s"${n(r("simulation")("cyclesPerSecond"), 0)} cycles/s, ${n(r("simulation")("wallSeconds"), 1)} s"
    ).map { case (k, v) => f"  $k%-30s $v" }.mkString("\n")
  }

  def markdown(r: ujson.Obj): String = {
    val cfg = r("configuration").obj.map { case (k, v) => s"| $k | ${v match { case ujson.Str(s) => s; case o => n(o) }} |" }
    // Built line by line: stripMargin would eat the leading `|` of interpolated rows.
    (Seq("# Regression report", "", "Generated by `make regress`; do not edit.", "", "```", table(r), "```", "",
      "| configuration | value |", "| --- | --- |") ++ cfg ++ Seq("")).mkString("\n")
  }
}
