package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.golden.{HitRecord, RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage
import rtaccel.testutil.{Seeded, Waves}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{AccelHarness, Backends, ControlWorkload, Environment, FieldDatapath, SimTop, SyntheticBvh}
import rtaccel.sim.mem.{Latency, MemoryParams}

import scala.util.Random

/** The whole accelerator's control path, with FieldDatapath's cheap
  * arithmetic: every ray checked against the golden traversal, under every
  * kind of back-pressure and memory behaviour. (The real arithmetic is
  * checked against Embree by the scene specs.)
  */
class RtAccelControlSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RtAccel (control path)"

  import ControlWorkload.{check, config, makeRays, treeOf}

  private val envs = Seq(
    "latency 1" -> Environment(MemoryParams(Latency.Fixed(1)), MemoryParams(Latency.Fixed(1))),
    "latency 10, stalls" -> Environment(
      MemoryParams(Latency.Fixed(10)),
      MemoryParams(Latency.Fixed(10)),
      rayGap = 0.3,
      hitRefuse = 0.5,
      memRefuse = 0.3
    ),
    "latency 100" -> Environment(MemoryParams(Latency.Fixed(100)), MemoryParams(Latency.Fixed(100)), hitRefuse = 0.1),
    "random 50-300, OOO" -> Environment(
      MemoryParams(Latency.Uniform(50, 300), maxOutstanding = 16),
      MemoryParams(Latency.Uniform(50, 300), maxOutstanding = 16),
      rayGap = 0.2,
      hitRefuse = 0.3,
      memRefuse = 0.2
    ),
    "in-order, cached" -> Environment(
      MemoryParams(Latency.Fixed(40), inOrder = true, cache = Some(rtaccel.sim.mem.CacheParams(mshrs = 4))),
      MemoryParams(Latency.Fixed(40), inOrder = true),
      hitRefuse = 0.2
    )
  )

  // Quantized layouts (4q, 8q) run in `make soak` (every layout), not here: their control is the wide layout's, and
  // their decoder is covered by the 4q cases of PrepFetchSpec, BboxIntersectSpec, TraversalSpec and RtAccelSceneSpec
  // (a 4q case here passed, about 37 s, over make test's budget).
  for (
    layout <- BvhLayout.all.filterNot(_.quantized); (ids, rayCount) <- Seq(2 -> 150, 4 -> 250, 16 -> 600)
    if layout == BvhLayout.Nori || layout == BvhLayout.Wide(4) || ids == 4
  ) {
    it should s"answer every ray exactly once, bit-exact with the golden model, with $ids ray IDs in every environment (layout ${layout.name})" in
      Seeded(s"RtAccelControl.${layout.name}.ids$ids") { rnd =>
        val cfg = config(layout, ids)
        Waves.onFailure(Backends.verilator) { annos =>
          test(new SimTop(cfg, FieldDatapath)).withAnnotations(annos) { dut =>
            var first = true
            for (((name, env), k) <- envs.zipWithIndex) {
              // Trees deeper than the stack: some rays must overflow and say so.
              val (img, _) = treeOf(layout, new Random(rnd.nextLong()))
              val rays = makeRays(rnd, rayCount)
              if (!first) dut.reset.poke(true.B)
              dut.clock.step(); dut.reset.poke(false.B)
              first = false
              val run = AccelHarness.run(dut, img, rays, env.copy(seed = rnd.nextLong() + k))
              check(cfg, img, rays, run.hits, s"$ids IDs, $name")
              assert(
                run.perf("raysIn") == rays.size && run.perf("hitsOut") == rays.size,
                s"$name: counters ${run.perf}"
              )
            }
          }
        }
      }
  }

  for (layout <- Seq(BvhLayout.Nori, BvhLayout.Wide(4)))
    it should s"flag stack overflow and invalid rays, never returning their hits (layout ${layout.name})" in Seeded(
      s"RtAccelControl.errors.${layout.name}"
    ) { rnd =>
      val (img, bound) = treeOf(layout, new Random(rnd.nextLong()), leafChance = 0.05)
      // Wide nodes: half the stack, so that full-width nodes along a path overflow it.
      val stack = if (layout == BvhLayout.Nori) bound else bound / 2
      val cfg = AccelConfig(
        numRayIds = 4,
        stackDepth = stack,
        maxNodes = 4096,
        maxTriangles = 4096,
        maxLeafSize = 4,
        layout = layout
      )
      val rays = makeRays(rnd, 300)
      val traces = rays.map(r => TraversalGolden.trace(cfg, img, FieldDatapath.Golden, r).hit)
      // The golden model must itself see both kinds of error, or this spec checks nothing.
      assert(traces.exists(h => (h.errors >> ErrorFlags.StackOverflow & 1) == 1), "no ray overflowed its stack")
      assert(traces.exists(h => (h.errors >> ErrorFlags.InvalidRay & 1) == 1), "no invalid ray")
      assert(traces.filter(_.errors != 0).forall(!_.hit), "a ray with an error reported a hit")
      Waves.onFailure(Backends.verilator) { annos =>
        test(new SimTop(cfg, FieldDatapath)).withAnnotations(annos) { dut =>
          val run = AccelHarness.run(
            dut,
            img,
            rays,
            Environment(MemoryParams(Latency.Fixed(5)), MemoryParams(Latency.Fixed(5)), seed = rnd.nextLong())
          )
          check(cfg, img, rays, run.hits, "errors")
        }
      }
    }

  for (layout <- Seq(BvhLayout.Nori, BvhLayout.Wide(4)))
    it should s"flag NaN and infinite scene data in memory, never answering a miss or a hit for it (layout ${layout.name})" in
      Seeded(s"RtAccelControl.badData.${layout.name}") { rnd =>
        val (clean, stack) = treeOf(layout, new Random(rnd.nextLong()))
        val (img, boxWords, vertexWords) = SyntheticBvh.corrupt(clean, new Random(rnd.nextLong()), share = 0.05)
        val cfg = AccelConfig(
          numRayIds = 8,
          stackDepth = stack,
          maxNodes = 4096,
          maxTriangles = 4096,
          maxLeafSize = 4,
          layout = layout
        )
        // Closest-hit rays: a shadow ray may stop at an occluder before it meets the bad word.
        val rays = makeRays(rnd, 300).map(_.copy(shadow = false))
        val traces = rays.map(r => TraversalGolden.trace(cfg, img, FieldDatapath.Golden, r).hit)
        val flagged = traces.count(h => (h.errors >> ErrorFlags.BadSceneData & 1) == 1)
        assert(flagged > 10, s"$flagged flagged rays: the test checks little")
        assert(traces.filter(_.errors != 0).forall(!_.hit), "a ray with an error reported a hit")
        Waves.onFailure(Backends.verilator) { annos =>
          test(new SimTop(cfg, FieldDatapath)).withAnnotations(annos) { dut =>
            val run = AccelHarness.run(
              dut,
              img,
              rays,
              Environment(MemoryParams(Latency.Fixed(5)), MemoryParams(Latency.Fixed(5)), seed = rnd.nextLong())
            )
            check(cfg, img, rays, run.hits, "bad scene data")
          }
        }
        info(
          s"$boxWords box and $vertexWords vertex words NaN/inf; $flagged of ${rays.size} rays flagged bad-scene-data, bit-exact with the golden model"
        )
      }

  it should "take the same number of cycles for the same inputs" in Seeded("RtAccelControl.determinism") { rnd =>
    val (img, stack) = treeOf(BvhLayout.Wide(4), new Random(rnd.nextLong()))
    val cfg = AccelConfig(numRayIds = 4, stackDepth = stack, maxNodes = 4096, maxTriangles = 4096, maxLeafSize = 4)
    val rays = makeRays(rnd, 200)
    val env = Environment(
      MemoryParams(Latency.Uniform(20, 80)),
      MemoryParams(Latency.Uniform(20, 80)),
      rayGap = 0.2,
      hitRefuse = 0.2,
      seed = rnd.nextLong()
    )
    Waves.onFailure(Backends.verilator) { annos =>
      test(new SimTop(cfg, FieldDatapath)).withAnnotations(annos) { dut =>
        val a = AccelHarness.run(dut, img, rays, env)
        dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
        val b = AccelHarness.run(dut, img, rays, env)
        assert(a.cycles == b.cycles && a.hits == b.hits, s"cycles ${a.cycles} vs ${b.cycles}")
      }
    }
  }
}
