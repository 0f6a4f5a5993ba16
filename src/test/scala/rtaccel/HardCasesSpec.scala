package rtaccel

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.regress.{Bridge, Chosen, Regress}
import rtaccel.scene.{HitsCsv, ScenePackage}
import rtaccel.testutil.{Seeded, Waves}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.{AccelHarness, Backends, Environment, SimTop}
import rtaccel.sim.mem.{Latency, MemoryParams}

import java.nio.file.{Files, Paths}
import scala.jdk.CollectionConverters._

/** The hard-case suite (scenes/hard/, made by `make hard-cases`) through the
  * RTL in the configuration built to be exact: FP32, watertight triangles,
  * conservative boxes. Every ray equals the golden model bit for bit, and
  * against each case's expectations (by construction, checked in exact
  * arithmetic) there is no leak, no false hit, no wrong primitive and no
  * refused ray. Round-to-nearest boxes are not held to this: they cull a node
  * whose face the ray touches exactly (docs/reports/speed-vs-error.md).
  */
class HardCasesSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RtAccel on the hard cases"

  private val bridge = Paths.get("nori-bridge/target/release/nori-bridge")
  private val hardDir = Paths.get("scenes/hard")

  private def cases: Seq[String] = {
    val listed = if (Files.isDirectory(hardDir))
      Files.list(hardDir).iterator.asScala.filter(d => Files.exists(d.resolve("expect.csv"))).toSeq
    else Nil
    assert(listed.nonEmpty, s"$hardDir has no hard cases: regenerate them with `make hard-cases`")
    listed.map(_.getFileName.toString).sorted
  }

  it should "have no leak, false hit, wrong primitive or refused ray in FP32 with watertight triangles and conservative boxes" in
    Seeded("HardCases.fp32-cons-wt") { rnd =>
      val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
      // The 4-wide layout, as `make regress` builds by default.
      val layout = BvhLayout.Wide(4)
      val cfg = AccelConfig(
        numRayIds = 16,
        stackDepth = 24,
        maxNodes = 1 << 13,
        maxTriangles = 1 << 12,
        maxLeafSize = 4,
        layout = layout
      )
      val chosen = Chosen(dp, FloatGolden(dp)).asInstanceOf[Chosen[Data, Any]]
      val mem = MemoryParams(Latency.Uniform(20, 120), maxOutstanding = 16)
      val env = Environment(mem, mem, rayGap = 0.1, hitRefuse = 0.1)
      Waves.onFailure(Backends.verilator) { annos =>
        test(new SimTop(cfg, dp)).withAnnotations(annos) { dut =>
          for ((c, k) <- cases.zipWithIndex) {
            val dir = Paths.get("build/test-scenes").resolve(s"hard-$c")
            Bridge.compile(
              bridge,
              hardDir.resolve(c).resolve(s"$c.xml"),
              dir,
              hardDir.resolve(c).resolve("rays.txt").toString,
              Seq("--reference", "double", "--bvh", layout.name)
            )
            val pkg = ScenePackage.load(dir)
            assert(pkg.misfits(cfg).isEmpty, s"$c: ${pkg.misfits(cfg)}")
            dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
            val run = AccelHarness.run(dut, pkg.image, pkg.rays, env.copy(seed = rnd.nextLong() + k))
            val differ = Regress.goldenCheck(cfg, pkg, pkg.rays, chosen, run.hits)
            assert(
              differ.isEmpty,
              s"$c: ${differ.size} rays differ from the golden model (printed above): ${differ.take(3)}"
            )
            val hits = dir.resolve(s"hits-${dp.name}.csv")
            HitsCsv.write(hits, run.hits)
            val s = Bridge.hardScore(
              bridge,
              dir,
              hits,
              hardDir.resolve(c).resolve("expect.csv"),
              dir.resolve(s"score-${dp.name}.json")
            )
            println(
              f"$c: ${pkg.rays.size} rays in ${run.cycles}%,d cycles, golden exact; leaks ${s("leaks")}, false hits ${s("false_hits")}, " +
                s"wrong prims ${s("wrong_prims")}, flagged ${s("flagged")}"
            )
            for (k <- Seq("leaks", "false_hits", "wrong_prims", "flagged"))
              assert(
                s(k).num == 0,
                s"$c: $k = ${s(k)}: rays ${s("lists")(k)}; see ${dir.resolve(s"score-${dp.name}.json")}"
              )
          }
        }
      }
    }
}
