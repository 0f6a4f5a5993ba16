package rtaccel.traversal

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.datapath.{
  RayPrepFromWords,
  BoxRounding,
  ExactBox,
  FloatDatapath,
  FloatGolden,
  KernelCase,
  KernelVectors,
  RayConsts,
  TriangleTest
}
import rtaccel.fp.{FloatFormat, FpOrder}
import rtaccel.testutil.Seeded
import rtaccel.AccelConfig
import rtaccel.bvh.{BvhLayout, BvhNode, QuantNode}
import rtaccel.sim.Backends

/** RayPrep feeding BboxIntersect, so a spec can drive raw rays and boxes. */
class BboxHarness(val cfg: AccelConfig, val dp: FloatDatapath) extends Module {
  private val k = cfg.boxLanes
  val io = IO(new Bundle {
    val valid = Input(Bool())

    /** o, d, tmin, tmax: eight FP32 words. */
    val ray = Input(Vec(8, UInt(32.W)))
    val boxMin = Input(Vec(k, Vec(3, UInt(32.W))))
    val boxMax = Input(Vec(k, Vec(3, UInt(32.W))))
    val present = Input(Vec(k, Bool()))
    val out = Valid(new BboxAnswer(cfg))
  })
  private val prep = RayPrepFromWords(dp, cfg, io.valid, io.ray)
  val prepLatency: Int = prep.latency
  private val box = Module(new BboxIntersect(cfg, dp))
  box.io.in.valid := prep.io.out.valid
  box.io.in.bits.ray := prep.io.out.bits.statics
  box.io.in.bits.tmax := prep.io.out.bits.tmax
  box.io.in.bits.boxMin := ShiftRegister(io.boxMin, prepLatency)
  box.io.in.bits.boxMax := ShiftRegister(io.boxMax, prepLatency)
  box.io.in.bits.present := ShiftRegister(io.present, prepLatency)
  val boxLatency: Int = box.latency
  io.out := box.io.out
}

/** RayPrep feeding BboxIntersect through the node decoder: a quantized node
  * record in, its slots decoded (BvhNode.decode, QuantNode) and tested.
  */
class BboxQuantHarness(val cfg: AccelConfig, val dp: FloatDatapath) extends Module {
  val io = IO(new Bundle {
    val valid = Input(Bool())
    val ray = Input(Vec(8, UInt(32.W)))
    val record = Input(UInt((cfg.layout.nodeBytes * 8).W))
    val out = Valid(new BboxAnswer(cfg))
  })
  private val prep = RayPrepFromWords(dp, cfg, io.valid, io.ray)
  private val node = BvhNode.decode(cfg, ShiftRegister(io.record, prep.latency))
  private val box = Module(new BboxIntersect(cfg, dp))
  box.io.in.valid := prep.io.out.valid
  box.io.in.bits.ray := prep.io.out.bits.statics
  box.io.in.bits.tmax := prep.io.out.bits.tmax
  box.io.in.bits.boxMin := VecInit(node.slots.map(_.boxMin.get))
  box.io.in.bits.boxMax := VecInit(node.slots.map(_.boxMax.get))
  box.io.in.bits.present := VecInit(node.slots.map(_.present))
  val latency: Int = prep.latency + box.latency
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
    val cfg =
      AccelConfig(numRayIds = 4, stackDepth = 4, layout = BvhLayout.Wide(k), boxFloat = dp.boxFmt, triFloat = dp.triFmt)
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
                assert(
                  hitHw == (hit && !ray.box.err),
                  s"cycle $cycle: ray ${r.where}, slot $s (${u.fold("empty")(_.where)}): hit $hitHw, golden ${hit && !ray.box.err}"
                )
                if (hitHw) {
                  dut.io.out.bits.near(s).expect(near.U, s"ray ${r.where}, slot $s: entry distance")
                  hits += 1
                }
                checked += 1
              }
              // The children's entry order (TraversalControl.order) agrees with the distances given out.
              val keys = (0 until k).map(s => FpOrder.keyOf(cfg.boxFloat, dut.io.out.bits.near(s).peek().litValue))
              for ((o, n) <- TraversalControl.orderOf(keys).zipWithIndex)
                dut.io.out.bits.order(n).expect(o.B, s"cycle $cycle: ray ${r.where}, pair $n: entry order")
            } else dut.io.out.valid.expect(false.B, s"cycle $cycle: nothing due")
            dut.clock.step()
          }
          assert(hits > checked / 20, s"only $hits of $checked lane tests hit: the sample checks little")
          info(s"$checked lane tests, $hits hits, latency $lat (prep ${dut.prepLatency} + box ${dut.boxLatency})")
        }
      }
  }

  {
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.Watertight, BoxRounding.Conservative)
    val layout = BvhLayout.Wide(4, quantized = true)
    val cfg = AccelConfig(numRayIds = 4, stackDepth = 4, layout = layout, boxFloat = dp.boxFmt, triFloat = dp.triFmt)
    it should s"decode quantized child boxes and test them bit-exact with the golden model, never missing a box the exact ray enters (4q, ${dp.name})" in
      Seeded("BboxIntersect.4q") { rnd =>
        val g = FloatGolden(dp)
        def f(w: BigInt) = java.lang.Float.intBitsToFloat(w.toInt)
        // Boxes the encoder takes: finite, not inverted (QuantEncode refuses the rest, as nori-bridge would).
        val pool = KernelVectors.bboxOutFile.filter(c =>
          (c.bmin ++ c.bmax).forall(w => f(w).isFinite) &&
            (0 until 3).forall(a => f(c.bmin(a)) <= f(c.bmax(a)))
        )
        def boxOf(c: KernelCase) = QuantEncode.Box(c.bmin.map(f), c.bmax.map(f))
        // Lane 0: the case's own box; the rest random boxes of the pool, some slots empty.
        val nodes = IndexedSeq.fill(3000)(pool(rnd.nextInt(pool.size))).flatMap { r =>
          val boxes = r +: Seq.fill(3)(pool(rnd.nextInt(pool.size)))
          val used = boxes.zipWithIndex.map { case (b, i) => if (i > 0 && rnd.nextInt(5) == 0) None else Some(b) }
          QuantEncode.leaves(4, used.map(_.map(boxOf))).map(bytes => (r, used, bytes))
        }
        assert(nodes.size > 1000, s"only ${nodes.size} nodes could be quantized")
        test(new BboxQuantHarness(cfg, dp)).withAnnotations(Backends.verilator) { dut =>
          dut.clock.setTimeout(0)
          val lat = dut.latency
          var (hits, exactHits, checked) = (0, 0, 0)
          for (cycle <- 0 until nodes.size + lat) {
            if (cycle < nodes.size) {
              val (r, _, bytes) = nodes(cycle)
              dut.io.valid.poke(true.B)
              for ((w, i) <- (r.o ++ r.d ++ Seq(r.tmin, r.tmax)).zipWithIndex) dut.io.ray(i).poke(w.U)
              dut.io.record.poke(BigInt(1, bytes.reverse).U)
            } else dut.io.valid.poke(false.B)
            if (cycle >= lat) {
              val (r, used, bytes) = nodes(cycle - lat)
              dut.io.out.valid.expect(true.B, s"cycle $cycle: the answer for ${r.where} is due ($lat cycles)")
              val (ray, tmax) = g.setup(r.o, r.d, r.tmin, r.tmax)
              val decoded = QuantNode.decodeSoft(4, bytes.toIndexedSeq.map(_ & 0xff))
              for ((u, s) <- used.zipWithIndex) {
                val (hit, near) = u.fold((false, BigInt(0)))(_ =>
                  g.boxTest(ray, tmax, decoded(s).boxMin.map(BigInt(_)), decoded(s).boxMax.map(BigInt(_)))
                )
                val hitHw = dut.io.out.bits.hit(s).peek().litToBoolean
                assert(
                  hitHw == (hit && !ray.box.err),
                  s"cycle $cycle: ray ${r.where}, slot $s: hit $hitHw, golden ${hit && !ray.box.err}"
                )
                if (hitHw) {
                  dut.io.out.bits.near(s).expect(near.U, s"ray ${r.where}, slot $s: entry distance"); hits += 1
                }
                // Conservative: the exact ray entering the exact (unquantized) box is a hit.
                for (
                  c <- u
                  if !ray.box.err && ExactBox.hit(dp.fmt, r.o, r.d, r.tmin, r.tmax, c.bmin, c.bmax).contains(true)
                ) {
                  assert(
                    hitHw,
                    s"ray ${r.where}, slot $s (${c.where}): the exact ray enters the exact box, the quantized test misses it"
                  )
                  exactHits += 1
                }
                checked += 1
              }
            }
            dut.clock.step()
          }
          assert(
            exactHits > checked / 20,
            s"only $exactHits of $checked slots are exact hits: the sample checks little"
          )
          info(
            s"$checked quantized slot tests, $hits hits ($exactHits exact hits, none missed; ${hits - exactHits} added by quantization and rounding), latency $lat"
          )
        }
      }
  }
}
