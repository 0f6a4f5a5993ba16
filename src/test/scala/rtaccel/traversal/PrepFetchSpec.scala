package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.mem._
import rtaccel.sim.mem._
import rtaccel.scene.MemoryImage
import rtaccel.testutil.Seeded
import rtaccel.golden.TraversalGolden
import rtaccel.scene.Records
import rtaccel.{AccelConfig, BoxTest, ErrorFlags}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.Backends

import scala.collection.mutable
import scala.util.Random

class PrepFetchSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "PrepFetch"

  private def cfgOf(layout: BvhLayout) =
    AccelConfig(numRayIds = 8, stackDepth = 4, maxNodes = 64, maxTriangles = 1024, maxLeafSize = 8, layout = layout)

  private def pokeToken(dut: PrepFetch, id: Int, node: Int, sp: Int): Unit = {
    val t = dut.io.in.bits
    t.rayId.poke(id.U); t.nodeIdx.poke(node.U); t.sp.poke(sp.U)
    for (a <- 0 until 3) t.dirNeg(a).poke((((id >> a) & 1) == 1).B)
    t.shadow.poke((id % 2 == 1).B); t.errors.poke(0.U)
  }

  /** Checks an output against the image: the token's ray, and each slot of the node decoded from its bytes. */
  private def expectFetched(
      cfg: AccelConfig,
      dut: PrepFetch,
      img: MemoryImage,
      expected: Map[Int, (Int, Int)],
      what: String
  ): Int = {
    val o = dut.io.out.bits
    val id = o.token.rayId.peek().litValue.toInt
    val (node, sp) = expected.getOrElse(id, fail(s"$what: output for ray $id, which has no request outstanding"))
    o.token.nodeIdx.expect(node.U, what); o.token.sp.expect(sp.U, what)
    o.token.shadow.expect((id % 2 == 1).B, what)
    val slots = Records.node(img, node)
    val grid = TraversalGolden.gridOf(cfg, img, node)
    // Random bytes make most records corrupt or too wide for this config: the flags must say so.
    val d = TraversalGolden.nodeView(cfg, slots, grid.map(_.bad))
    for ((rec, s) <- slots.zipWithIndex) {
      val hw = o.node.slots(s)
      hw.present.expect(d.present(s).B, s"$what: slot $s used")
      if (d.present(s)) {
        val ref = d.view.refs(s)
        hw.child.isLeaf.expect(ref.isLeaf.B, s"$what: slot $s leaf")
        assert(
          (hw.child.index.peek().litValue & ((BigInt(1) << (if (ref.isLeaf) cfg.triIndexBits
                                                            else cfg.nodeIndexBits)) - 1)) == ref.index,
          s"$what: slot $s index"
        )
        if (ref.isLeaf) hw.child.count.expect(ref.count.U, s"$what: slot $s count")
      }
      for (a <- 0 until 3) grid match {
        case None =>
          hw.boxMin.get(a).expect(rec.boxMin(a).U, s"$what: slot $s min[$a]")
          hw.boxMax.get(a).expect(rec.boxMax(a).U, s"$what: slot $s max[$a]")
        case Some(g) =>
          hw.qMin.get(a).expect(g.qMin(s)(a).U, s"$what: slot $s qMin[$a]")
          hw.qMax.get(a).expect(g.qMax(s)(a).U, s"$what: slot $s qMax[$a]")
      }
    }
    for (g <- grid; a <- 0 until 3) {
      o.node.grid.get.origin(a).expect(g.origin(a).U, s"$what: origin[$a]")
      o.node.grid.get.exp(a).expect(g.exp(a).U, s"$what: exp[$a]")
    }
    if (cfg.layout == BvhLayout.Nori) o.node.axis.expect(d.view.axis.U, s"$what: axis")
    o.node.errors.expect(d.view.errors.U, s"$what: errors ${ErrorFlags.describe(o.node.errors.peek().litValue)}")
    id
  }

  // 4q: random bytes through the quantized decode (rounding adds, NaN scales, corrupt meta bytes); 4q grid: the same
  // bytes kept raw for the grid box test (bad scales and non-finite origins flagged).
  private val q4 = BvhLayout.Wide(4, quantized = true)
  for (cfg <- Seq(BvhLayout.Nori, BvhLayout.Wide(4), q4).map(cfgOf) :+ cfgOf(q4).copy(boxTest = BoxTest.Grid)) {
    val layout = cfg.layout
    val name = layout.name + (if (cfg.gridBox) " grid" else "")
    it should s"pair each response with its ray when memory answers in reverse order (layout $name)" in {
      val img = SyntheticImage(nodes = 64, tris = 4, new Random(11), layout)
      test(new PrepFetch(cfg)).withAnnotations(Backends.treadle) { dut =>
        dut.io.nodeBase.poke(img.nodeOffset.U)
        dut.io.mem.resp.valid.poke(false.B)
        dut.io.mem.req.ready.poke(false.B) // memory busy: all eight queue up first
        val reqs = mutable.ArrayBuffer.empty[(Int, Long)]
        val expected = (0 until 8).map(id => id -> ((id * 7 + 3) % 64, id % 4)).toMap
        for (id <- 0 until 8) {
          dut.io.in.valid.poke(true.B)
          pokeToken(dut, id, expected(id)._1, expected(id)._2)
          dut.io.in.ready.expect(true.B)
          dut.clock.step()
        }
        dut.io.in.valid.poke(false.B)
        dut.io.waiting.expect(8.U)
        dut.io.mem.req.ready.poke(true.B)
        while (dut.io.mem.req.valid.peek().litToBoolean) {
          reqs += ((dut.io.mem.req.bits.tag.peek().litValue.toInt, dut.io.mem.req.bits.addr.peek().litValue.toLong))
          dut.clock.step()
        }
        assert(reqs.map(_._1) == (0 until 8), s"requests leave in arrival order: $reqs")
        for ((tag, addr) <- reqs) assert(addr == img.nodeAddr(expected(tag)._1), s"ray $tag: address $addr")
        dut.io.waiting.expect(8.U)
        for ((tag, addr) <- reqs.reverse) {
          dut.io.mem.resp.valid.poke(true.B)
          dut.io.mem.resp.bits.tag.poke(tag.U)
          dut.io.mem.resp.bits.data.poke(img.readLE(addr, layout.nodeBytes).U)
          dut.clock.step()
          dut.io.mem.resp.valid.poke(false.B)
          for (_ <- 1 until PrepFetch.latency(cfg)) { dut.io.out.valid.expect(false.B); dut.clock.step() }
          dut.io.out.valid.expect(true.B)
          assert(expectFetched(cfg, dut, img, expected, s"response for ray $tag") == tag)
        }
        dut.clock.step()
        dut.io.out.valid.expect(false.B)
        dut.io.waiting.expect(0.U)
      }
    }

    // The grid decode changes only what a node carries, not the queueing: its reverse-order case above suffices.
    if (!cfg.gridBox)
      it should s"lose and duplicate nothing under random stalls and out-of-order memory (layout $name)" in Seeded(
        s"PrepFetch.random.${layout.name}"
      ) { rnd =>
        val img = SyntheticImage(nodes = 64, tris = 4, new Random(rnd.nextLong()), layout)
        // 4q: the decoder's 24 FP32 adds (6 planes x 4 slots) make treadle take minutes for these 3200 cycles; Verilator builds in about 30 s.
        val backend = if (layout.quantized) Backends.verilator else Backends.treadle
        test(new PrepFetch(cfg)).withAnnotations(backend) { dut =>
          val model = new MemorySystemModel(
            img,
            layout.nodeBytes,
            MemoryParams(latency = Latency.Uniform(1, 30), maxOutstanding = 5, seed = rnd.nextLong()),
            "node"
          )
          val mem = new MemPortHarness(dut.io.mem, model, refuse = 0.3, rnd = rnd)
          dut.io.nodeBase.poke(img.nodeOffset.U)
          val outstanding = mutable.Map.empty[Int, (Int, Int)]
          var sent, received = 0
          for (cycle <- 0 until 3000) {
            val free = (0 until 8).filterNot(outstanding.contains)
            val offer = free.nonEmpty && rnd.nextBoolean()
            val id = if (offer) free(rnd.nextInt(free.size)) else 0
            val (node, sp) = (rnd.nextInt(64), rnd.nextInt(5))
            dut.io.in.valid.poke(offer.B)
            if (offer) pokeToken(dut, id, node, sp)
            if (dut.io.out.valid.peek().litToBoolean) {
              val got = expectFetched(cfg, dut, img, outstanding.toMap, s"cycle $cycle")
              outstanding.remove(got); received += 1
            }
            val accepted = offer && dut.io.in.ready.peek().litToBoolean
            mem.drive()
            dut.clock.step(); mem.tick()
            if (accepted) { outstanding(id) = (node, sp); sent += 1 }
          }
          dut.io.in.valid.poke(false.B)
          for (_ <- 0 until 200) {
            if (dut.io.out.valid.peek().litToBoolean) {
              outstanding.remove(expectFetched(cfg, dut, img, outstanding.toMap, "drain")); received += 1
            }
            mem.drive(); dut.clock.step(); mem.tick()
          }
          assert(
            outstanding.isEmpty && sent == received,
            s"sent $sent, received $received, still waiting: ${outstanding.keys}"
          )
          // The model's return channel moves 16 bytes a cycle, so wider nodes take longer.
          assert(sent > 500 * 32 / layout.nodeBytes, s"only $sent fetches in 3000 cycles")
        }
      }
  }
}
