package rtaccel.datapath

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FloatFormat
import rtaccel.testutil.Seeded
import rtaccel.report.{ClosedMesh, LeakCount}

/** Zero leaks of the watertight datapath on a closed mesh (rays from inside
  * aimed exactly at every vertex and edge midpoint), in FP32 and the narrow
  * formats, on the golden model (bit-exact with the hardware). Offset 0 for
  * every format; offset 1e4 only where the format still resolves a radius-1
  * mesh there (FP32: spacing 2^-10).
  */
class WatertightLeakSpec extends AnyFlatSpec {
  private val cases = Seq(FloatFormat.FP32 -> 1e4) ++ (FloatFormat.FP32 +: GoldenRun.narrowFormats).map(_ -> 0.0)
  for ((fmt, offset) <- cases) {
    s"watertight ${fmt.name}" should s"not leak on the level-3 closed mesh at offset $offset" in
      Seeded(s"WatertightLeakSpec ${fmt.name} $offset") { rng =>
        val g = FloatGolden(FloatDatapath(fmt, TriangleTest.Watertight, BoxRounding.Nearest))
        val mesh = ClosedMesh(3, 1.0, offset, rng)
        val r = LeakCount(g, mesh, origins = 2, radius = 1.0, offset = offset, rng)
        assert(r.vertexLeaks == 0 && r.edgeLeaks == 0, s"leaks: $r")
        assert(r.vertexRays > 0 && r.edgeRays > 0)
        info(s"$r")
      }
  }

  "the leak counter" should "see Moller-Trumbore leak on the same FP32 mesh (it can find leaks)" in
    Seeded("WatertightLeakSpec mt") { rng =>
      val g = FloatGolden(FloatDatapath(FloatFormat.FP32, TriangleTest.Moller, BoxRounding.Nearest))
      val r = LeakCount(g, ClosedMesh(3, 1.0, 0.0, rng), origins = 2, radius = 1.0, offset = 0.0, rng)
      assert(r.vertexLeaks + r.edgeLeaks > 0, s"MT did not leak: $r")
      info(s"$r")
    }
}
