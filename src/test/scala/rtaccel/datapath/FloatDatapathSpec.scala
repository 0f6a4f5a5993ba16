package rtaccel.datapath

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FloatFormat
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

/** The hardware units (ray prep + box, ray prep + triangle) on Verilator,
  * every output bit against its reference:
  *  - FP32 RNE: the HLS twins' outputs, every line of the .out files;
  *  - other formats and the conservative mode: the golden model, on every
  *    hard case plus a seeded sample of the .out files' random inputs.
  * One Verilator build per datapath variant: 5 in all (the suite's budget).
  */
class FloatDatapathSpec extends AnyFlatSpec with ChiselScalatestTester {
  import FloatDatapathSpec._
  private val f32 = FloatFormat.FP32

  private def runOn(dp: FloatDatapath, work: DatapathDriver.Work): Unit =
    test(new DatapathHarness(dp)).withAnnotations(Backends.verilator) { dut =>
      val bad = DatapathDriver.run(dut, work)
      assert(bad.isEmpty, s"${dp.name}:\n" + bad.mkString("\n"))
      info(s"${dp.name}: ${work.boxes.size} box + ${work.prims.size} triangle cases bit-exact; latency prep " +
        s"${dut.prepLatency}, box ${dut.boxLatency}, triangle ${dut.primLatency}")
    }

  "e8m23_mt_rne" should "match the HLS bbox.out and prim_mt.out bit for bit on every line" in {
    runOn(
      FloatDatapath(f32, TriangleTest.Moller, BoxRounding.Nearest),
      DatapathDriver.Work(
        KernelVectors.bboxOutFile.map(c => c -> GoldenRun.boxOf(c)),
        KernelVectors.mtOutFile.map(c => c -> GoldenRun.primOf(c))
      )
    )
  }

  "e8m23_wt_cons" should "match prim_wt.out bit for bit, and the golden conservative box on every line" in {
    val dp = FloatDatapath(f32, TriangleTest.Watertight, BoxRounding.Conservative)
    val g = FloatGolden(dp)
    runOn(
      dp,
      DatapathDriver.Work(
        KernelVectors.bboxOutFile.map(c => c -> GoldenRun.box(g, c)),
        KernelVectors.wtOutFile.map(c => c -> GoldenRun.primOf(c))
      )
    )
  }

  for (dp <- narrowVariants) {
    dp.name should s"match its golden model bit for bit on the hard cases and $RandomSample random cases" in {
      Seeded(s"FloatDatapathSpec ${dp.name}") { rng =>
        val g = FloatGolden(dp)
        val boxes = KernelVectors.bboxHard ++ sample(KernelVectors.bboxOutFile, rng)
        val prims = KernelVectors.triHard ++ sample(KernelVectors.mtOutFile, rng)
        runOn(
          dp,
          DatapathDriver.Work(boxes.map(c => c -> GoldenRun.box(g, c)), prims.map(c => c -> GoldenRun.prim(g, c)))
        )
      }
    }
  }
}

object FloatDatapathSpec {

  /** Random cases per narrow variant (drawn from the .out files' inputs). */
  val RandomSample = 20000
  val narrowVariants: Seq[FloatDatapath] = Seq(
    FloatDatapath(FloatFormat(8, 15), TriangleTest.Watertight, BoxRounding.Conservative),
    FloatDatapath(FloatFormat(8, 10), TriangleTest.Moller, BoxRounding.Nearest),
    FloatDatapath(FloatFormat(6, 9), TriangleTest.Watertight, BoxRounding.Conservative)
  )
  // Split formats (e8m10e8m23_wt_cons) are checked on the whole accelerator, ray by ray,
  // in RtAccelSceneSpec; one more Verilator build here would exceed make test's budget.

  /** A seeded sample of a .out file's inputs (its own outputs are FP32 and unused here). */
  def sample(cases: IndexedSeq[KernelCase], rng: scala.util.Random): IndexedSeq[KernelCase] =
    IndexedSeq.fill(RandomSample)(cases(rng.nextInt(cases.size)))
}
