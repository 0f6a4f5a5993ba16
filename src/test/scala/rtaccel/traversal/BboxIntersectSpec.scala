package rtaccel.traversal

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{RayPrepFromWords, BoxRounding, FloatDatapath, FloatGolden, KernelCase, KernelVectors, RayConsts, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.testutil.{Backends, Seeded}
import rtaccel.{AccelConfig, BvhLayout}

/** RayPrep feeding BboxIntersect, so a spec can drive raw rays and boxes. */
class BboxHarness(val cfg: AccelConfig, val dp: FloatDatapath) extends Module {
  private val k = cfg.boxLanes
  val io = IO(new Bundle {
    val valid   = Input(Bool())
    /** o, d, tmin, tmax: eight FP32 words. */
    val ray     = Input(Vec(8, UInt(32.W)))
    val boxMin  = Input(Vec(k, Vec(3, UInt(32.W))))
    val boxMax  = Input(Vec(k, Vec(3, UInt(32.W))))
    val present = Input(Vec(k, Bool()))
    val out     = Valid(new BboxAnswer(cfg))
  })
  private val prep = RayPrepFromWords(dp, cfg, io.valid, io.ray)
  val prepLatency: Int = prep.latency
  private val box = Module(new BboxIntersect(cfg, dp))
  box.io.in.valid        := prep.io.out.valid
  box.io.in.bits.ray     := prep.io.out.bits.statics
  box.io.in.bits.tmax    := prep.io.out.bits.tmax
  box.io.in.bits.boxMin  := ShiftRegister(io.boxMin, prepLatency)
  box.io.in.bits.boxMax  := ShiftRegister(io.boxMax, prepLatency)
  box.io.in.bits.present := ShiftRegister(io.present, prepLatency)
  val boxLatency: Int = box.latency
  io.out := box.io.out
}

/** BboxIntersect: K lanes, one node per cycle (II = 1), each lane's hit and
  * entry distance bit-exact with the golden box test, exactly `latency`
  * cycles after its input; an empty slot never hits, whatever its box holds.
  */
class BboxIntersectSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "BboxIntersect"

  for (k <- Seq(4)) {
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
    val cfg = AccelConfig(numRayIds = 4, stackDepth = 4, layout = BvhLayout.Wide(k), float = dp.fmt)
    it should s"test a ray against $k child boxes per cycle, every lane bit-exact with the golden model (${dp.name})" in
      Seeded(s"BboxIntersect.k$k") { rnd =>
        val g = FloatGolden(dp)
        // Hard cases first (their rays against their own boxes in lane 0, other cases' boxes in the rest), then a random sample.
        val pool = KernelVectors.bboxOutFile
        val rays = KernelVectors.bboxHard ++ IndexedSeq.fill(3000)(pool(rnd.nextInt(pool.size)))
        test(new BboxHarness(cfg, dp)).withAnnotations(Backends.verilator) { dut =>
          dut.clock.setTimeout(0)
          val lat = dut.prepLatency + dut.boxLatency
          val due = scala.collection.mutable.Queue.empty[(Int, KernelCase, Seq[Option[KernelCase]])]
          var hits, checked = 0
          for (cycle <- 0 until rays.size + lat) {
            if (cycle < rays.size) {
              val r = rays(cycle)
              // Lane 0 tests the case's own box; the others random boxes, some slots empty.
              val boxes = r +: Seq.fill(k - 1)(pool(rnd.nextInt(pool.size)))
              val used = boxes.map(b => if (rnd.nextInt(5) == 0) None else Some(b))
              dut.io.valid.poke(true.B)
              for ((w, i) <- (r.o ++ r.d ++ Seq(r.tmin, r.tmax)).zipWithIndex) dut.io.ray(i).poke(w.U)
              for ((b, s) <- boxes.zipWithIndex; a <- 0 until 3) {
                dut.io.boxMin(s)(a).poke(b.bmin(a).U); dut.io.boxMax(s)(a).poke(b.bmax(a).U)
              }
              for ((u, s) <- used.zipWithIndex) dut.io.present(s).poke(u.isDefined.B)
              due.enqueue((cycle + lat, r, used))
            } else dut.io.valid.poke(false.B)
            if (due.headOption.exists(_._1 == cycle)) {
              val (_, r, used) = due.dequeue()
              dut.io.out.valid.expect(true.B, s"cycle $cycle: the answer for ${r.where} is due ($lat cycles)")
              val (ray, tmax) = g.setup(r.o, r.d, r.tmin, r.tmax)
              for ((u, s) <- used.zipWithIndex) {
                val (hit, near) = u.fold((false, BigInt(0)))(b => g.boxTest(ray, tmax, b.bmin, b.bmax))
                val hitHw = dut.io.out.bits.hit(s).peek().litToBoolean
                assert(hitHw == (hit && !ray.err), s"cycle $cycle: ray ${r.where}, slot $s (${u.fold("empty")(_.where)}): hit $hitHw, golden ${hit && !ray.err}")
                if (hitHw) {
                  dut.io.out.bits.near(s).expect(near.U, s"ray ${r.where}, slot $s: entry distance")
                  hits += 1
                }
                checked += 1
              }
            } else dut.io.out.valid.expect(false.B, s"cycle $cycle: nothing due")
            dut.clock.step()
          }
          assert(hits > checked / 20, s"only $hits of $checked lane tests hit: the sample checks little")
          info(s"$checked lane tests, $hits hits, latency $lat (prep ${dut.prepLatency} + box ${dut.boxLatency})")
        }
      }
  }
}
