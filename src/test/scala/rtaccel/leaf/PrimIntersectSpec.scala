package rtaccel.leaf

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.datapath.{RayPrepFromWords, BoxRounding, FloatDatapath, FloatGolden, KernelVectors, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.testutil.Seeded
import rtaccel.sim.Backends

/** RayPrep feeding PrimIntersect, so a spec can drive raw rays and triangles. */
class PrimHarness(val cfg: AccelConfig, val dp: FloatDatapath) extends Module {
  val io = IO(new Bundle {
    val valid = Input(Bool())

    /** o, d, tmin, tmax: eight FP32 words. */
    val ray = Input(Vec(8, UInt(32.W)))

    /** p0, p1, p2: nine FP32 words (the rest of the record is zero). */
    val verts = Input(Vec(9, UInt(32.W)))
    val out = Valid(new PrimAnswer(cfg))
  })
  private val prep = RayPrepFromWords(dp, cfg, io.valid, io.ray)
  val prepLatency: Int = prep.latency
  private val prim = Module(dp.prim(cfg))
  prim.io.in.valid := prep.io.out.valid
  prim.io.in.bits.ray := prep.io.out.bits.statics
  prim.io.in.bits.tmax := prep.io.out.bits.tmax
  prim.io.in.bits.triangle := ShiftRegister(io.verts.asUInt, prepLatency).pad(TriangleRecord.RecordBytes * 8)
  val primLatency: Int = prim.latency
  io.out := prim.io.out
}

/** PrimIntersect: one ray/triangle test per cycle (II = 1), each answer
  * (hit, t, u, v) bit-exact with the golden kernel exactly `latency` cycles
  * after its input, on the hard triangle cases and a seeded sample of the
  * HLS vector file. (FloatDatapathSpec checks every line of the HLS outputs
  * for the FP32 units, alongside the box lane.)
  */
class PrimIntersectSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PrimIntersect"

  private val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
  private val cfg = AccelConfig(numRayIds = 4, stackDepth = 4, boxFloat = dp.boxFmt, triFloat = dp.triFmt)

  it should s"answer one triangle per cycle, bit-exact with the golden kernel at a fixed latency (${dp.name})" in
    Seeded("PrimIntersect.fp32wt") { rnd =>
      val g = FloatGolden(dp)
      val pool = KernelVectors.mtOutFile
      val cases = KernelVectors.triHard ++ IndexedSeq.fill(3000)(pool(rnd.nextInt(pool.size)))
      test(new PrimHarness(cfg, dp)).withAnnotations(Backends.verilator) { dut =>
        dut.clock.setTimeout(0)
        val lat = dut.prepLatency + dut.primLatency
        var hits = 0
        val sent = collection.mutable.ArrayBuffer.empty[Boolean] // valid in, by cycle
        for (cycle <- 0 until cases.size + lat) {
          // Random one-cycle gaps: the answer must follow its own input, not a count of inputs.
          val send = cycle < cases.size && rnd.nextInt(8) != 0
          dut.io.valid.poke(send.B)
          if (cycle < cases.size) {
            val c = cases(cycle)
            for ((w, i) <- (c.o ++ c.d ++ Seq(c.tmin, c.tmax)).zipWithIndex) dut.io.ray(i).poke(w.U)
            for ((w, i) <- c.verts.zipWithIndex) dut.io.verts(i).poke(w.U)
          }
          sent += send
          dut.clock.step()
          // The output is valid exactly when the input `lat` cycles ago was.
          val from = cycle + 1 - lat
          val due = from >= 0 && from < cases.size && sent(from)
          dut.io.out.valid.expect(due.B, s"cycle ${cycle + 1}: valid out exactly $lat cycles after valid in")
          if (due) {
            val c = cases(from)
            val (ray, tmax) = g.setup(c.o, c.d, c.tmin, c.tmax)
            val e = g.primTest(ray, tmax, c.verts)
            val hit = e.hit && !ray.tri.err
            dut.io.out.bits.hit.expect(hit.B, s"${c.where}: hit")
            if (hit) {
              dut.io.out.bits.t.expect(e.t.U, s"${c.where}: t")
              dut.io.out.bits.u.expect(e.u.U, s"${c.where}: u")
              dut.io.out.bits.v.expect(e.v.U, s"${c.where}: v")
              hits += 1
            }
          }
        }
        assert(hits > cases.size / 20, s"only $hits hits in ${cases.size} cases: the sample checks little")
        info(s"${cases.size} cases, $hits hits, latency $lat (prep ${dut.prepLatency} + triangle ${dut.primLatency})")
      }
    }

}
