package rtaccel.sweep

import chisel3._
import chiseltest._
import firrtl2.options.TargetDirAnnotation
import rtaccel.AccelConfig
import rtaccel.golden.HitRecord
import rtaccel.regress.{RegressArgs, Report}
import rtaccel.scene.ScenePackage
import rtaccel.sim.{AccelHarness, SimTop}

/** The speed half of a sweep point: `speedRays` rays of each speed run,
  * strided over the set, through the RTL under Verilator (one build per
  * configuration, reused across runs), with `make regress`'s default memory
  * (the ZC706's DDR3 shared by both ports at a 200 MHz fabric clock, 100 ns
  * latency), the ray IDs of the ZC706 configuration (AccelConfig.zc706). Every simulated ray must equal the golden answer;
  * a mismatch stops the sweep (a wrong design has no speed worth reporting).
  */
object SpeedRuns {

  /** `n` rays spread evenly over `rays` (all of them if there are no more than `n`). */
  def sample[A](rays: IndexedSeq[A], n: Int): IndexedSeq[A] =
    if (rays.size <= n) rays else IndexedSeq.tabulate(n)(i => rays((i.toLong * rays.size / n).toInt))

  def measure(
      a: SweepArgs,
      cfg: AccelConfig,
      runs: Seq[(String, ScenePackage)],
      golden: Map[String, Map[Long, HitRecord]]
  ): Map[String, ujson.Value] = {
    if (runs.isEmpty) return Map.empty
    val annos = Seq(
      VerilatorBackendAnnotation,
      chiseltest.internal.CachingAnnotation,
      TargetDirAnnotation(s"build/sim/sweep/${a.name}")
    )
    val out = Map.newBuilder[String, ujson.Value]
    RawTester.test(new SimTop(cfg, a.dp), annos) { dut =>
      for ((run, p) <- runs) {
        // An even stride over the whole set, not its first rays: a camera's first
        // rows (sky, for the dragon) would time a different workload.
        val rays = sample(p.rays, a.speedRays)
        val args = RegressArgs(
          p.dir,
          a.sweep,
          rounding = a.rounding.tag,
          triangle = a.test.tag,
          numRayIds = cfg.numRayIds,
          seed = a.seed
        )
        dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
        val t = System.nanoTime()
        val r = AccelHarness.run(dut, p.image, rays, args.environment)
        val sim = (System.nanoTime() - t) / 1e9
        val bad = SweepPoint.sameAnswers(rays.map(x => x.number -> x).toMap, r.hits, golden(run))
        require(
          bad == 0,
          s"${a.name} $run: $bad of ${rays.size} RTL answers differ from the golden model (seed ${a.seed})"
        )
        val s = Report.stats(args, cfg, a.dp.name, rays.size, r, sim, sim, 0, r.hits.count(_.errors != 0))
        println(
          f"sweep ${a.name}: $run RTL ${rays.size} rays ${r.cycles}%,d cycles ${s("raysPerCycle").num}%.4f rays/cycle " +
            f"(${s("efficiency").num}%.2f of bound, ${s("boundLimitedBy").str})"
        )
        out += run -> ujson.Obj(
          "rays" -> rays.size,
          "cycles" -> r.cycles.toDouble,
          "rays_per_cycle" -> s("raysPerCycle"),
          "bound_rays_per_cycle" -> s("boundRaysPerCycle"),
          "share_of_bound" -> s("efficiency"),
          "bound_limited_by" -> s("boundLimitedBy"),
          "golden_mismatches" -> bad,
          "node_tests_per_ray" -> s("nodeTestsPerRay"),
          "tri_tests_per_ray" -> s("triangleTestsPerRay"),
          "dram_bytes_per_ray" -> s("dramBytesPerRay"),
          "bound_terms" -> s("boundTerms"),
          "memory" -> args.describeMemory,
          "ray_ids" -> cfg.numRayIds
        )
      }
    }
    out.result()
  }
}
