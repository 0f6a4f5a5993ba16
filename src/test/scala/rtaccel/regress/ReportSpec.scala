package rtaccel.regress

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.{RunResult, Snapshot}
import rtaccel.sim.mem.{DramStats, MemStats}

/** The bound: one term per hardware resource, the least wins, and nothing
  * the test bench chose is a term.
  */
class ReportSpec extends AnyFlatSpec {
  behavior of "Report.Bound"

  private def perf(box: Long, tri: Long, decisions: Long, leafReturns: Long = 0) =
    Map[String, BigInt]("boxTests" -> box, "triTests" -> tri, "decisions" -> decisions, "leafReturns" -> leafReturns)

  it should "take the least of box lanes, triangle lanes, control and DRAM, and name it" in {
    // 100 rays: 20 node tests, 4 triangle tests, 25 decisions and 640 DRAM bytes per ray.
    val dram = Some(DramStats(cycles = 1000, bytes = 64000, bytesPerCycle = 64, burstBytes = 64, busyCycles = 1000))
    val b = Report.Bound(100, perf(2000, 400, 2500), dram, 64000)
    assert(b.terms.toMap == Map("boxLanes" -> 0.05, "triangleLanes" -> 0.25, "control" -> 0.04, "dram" -> 0.1))
    assert(b.limitedBy == "control" && b.raysPerCycle == 0.04)
    val ddrBound = Report.Bound(100, perf(200, 40, 250), dram, 64000)
    assert(ddrBound.limitedBy == "dram" && ddrBound.raysPerCycle == 0.1)
  }

  it should "count control by its busier lane: box results or leaf returns" in {
    // 10 rays: 30 decisions, 12 of them leaf returns: the box-result lane makes 1.8 per ray.
    assert(Report.Bound(10, perf(18, 5, 30, 12), None, 0).terms.toMap.apply("control") == 1.0 / 1.8)
    // 25 leaf returns of 40: the leaf-return lane is the busier, 2.5 per ray.
    assert(Report.Bound(10, perf(15, 5, 40, 25), None, 0).terms.toMap.apply("control") == 1.0 / 2.5)
  }

  it should "have no DRAM term on chip, and only the four named terms" in {
    val b = Report.Bound(10, perf(10, 100, 20), None, 0)
    assert(b.terms.map(_._1) == Seq("boxLanes", "triangleLanes", "control") && b.limitedBy == "triangleLanes")
    assert(b.terms.map(_._1).forall(Report.Bound.Terms.contains))
  }

  it should "write the bound, its limiter, its terms and DRAM bytes per ray into stats" in {
    def port(name: String, record: Int, dramBytes: Long) =
      MemStats(name, 1000, record, 50, 50, dramBytes, 0, 0, 0, 0, 0, 0, 0, 0)
    val r = RunResult(
      Nil,
      1000,
      perf(400, 40, 300) ++ Map[String, BigInt]("inFlightSum" -> 5000),
      port("node", 32, 3200),
      port("triangle", 48, 6400),
      Some(DramStats(1000, 9600, 64, 64, 150))
    )
    val s = Report.stats(
      RegressArgs(java.nio.file.Paths.get("p"), java.nio.file.Paths.get("o")),
      rtaccel.AccelConfig.zc706,
      "dp",
      20,
      r,
      1,
      1,
      0,
      0
    )
    assert(s("dramBytesPerRay").num == 480 && s("nodeBytesPerRay").num == 80)
    assert(s("boundLimitedBy").str == "boxLanes" && s("boundRaysPerCycle").num == 0.05)
    assert(s("boundTerms")("dram").num == 64.0 / 480 && s("memory")("dram")("busyShare").num == 0.15)
  }

  it should "measure the window between its snapshots: the rays answered there, and its resources' busy share" in {
    def port(name: String) = MemStats(name, 1000, 32, 50, 50, 0, 0, 0, 0, 0, 0, 0, 0, 0)
    // 100 rays in 1000 cycles; between the 20th and the 80th answer (cycles 300 to 800), 60 rays, 450 node tests,
    // 100 triangle tests and 400 decisions: box lanes busy 450 of 500 cycles.
    val a = Snapshot(20, 300, perf(250, 50, 300), None)
    val b = Snapshot(80, 800, perf(700, 150, 700), None)
    val r = RunResult(
      Nil,
      1000,
      perf(1000, 200, 1100) ++ Map[String, BigInt]("inFlightSum" -> 0),
      port("node"),
      port("triangle"),
      None,
      Some((a, b))
    )
    def stats(r: RunResult) = Report.stats(
      RegressArgs(java.nio.file.Paths.get("p"), java.nio.file.Paths.get("o")),
      rtaccel.AccelConfig.zc706,
      "dp",
      100,
      r,
      1,
      1,
      0,
      0
    )
    val w = stats(r)("steady")
    assert(w("rays").num == 60 && w("cycles").num == 500 && w("raysPerCycle").num == 60.0 / 500)
    assert(w("boundLimitedBy").str == "boxLanes" && math.abs(w("efficiency").num - 450.0 / 500) < 1e-12)
    assert(stats(r.copy(window = None))("steady") == ujson.Null)
    assert(RunResult.windowHits(100) == Some((20, 80)) && RunResult.windowHits(1) == None)
  }
}
