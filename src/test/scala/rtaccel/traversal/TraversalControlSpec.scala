package rtaccel.traversal

import chisel3._
import chisel3.util.Valid
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.fp.FpOrder
import rtaccel.golden.ControlGolden
import rtaccel.golden.ControlGolden._
import rtaccel.testutil.Seeded
import rtaccel.{AccelConfig, ErrorFlags}
import rtaccel.bvh.BvhLayout
import rtaccel.sim.Backends

import scala.collection.mutable
import scala.util.Random

/** TraversalControl cycle by cycle against ControlGolden, for every layout:
  * crafted walks (near child by axis in the nori layout; nearest-first with
  * ties to the lower slot in the wide ones), overflow, errors, occlusion, and
  * random traffic from interleaved rays with the output checked exactly
  * `latency` cycles after each input.
  */
/** TraversalControl with each lane's output resolved (TraversalControl.resolve) as Traversal resolves it after
  * its lane register, here without one: the lanes' outputs as they leave the unit.
  */
class ResolvedControl(cfg: AccelConfig) extends Module {
  private val c = Module(new TraversalControl(cfg))
  val latency: Int = c.latency
  val io = IO(new Bundle {
    val in = Flipped(Valid(new ControlIn(cfg)))
    val out = Valid(new ControlOut(cfg))
    val ret = Flipped(Valid(new ReturnIn(cfg)))
    val retOut = Valid(new ControlOut(cfg))
  })
  c.io.in := io.in
  c.io.ret := io.ret
  for ((o, d) <- Seq(io.out -> c.io.out, io.retOut -> c.io.retOut)) {
    o.valid := d.valid
    o.bits := TraversalControl.resolve(cfg, d.bits)
  }
}

class TraversalControlSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "TraversalControl"

  private def cfgOf(layout: BvhLayout, stackDepth: Int = 5, ids: Int = 8) =
    AccelConfig(
      numRayIds = ids,
      stackDepth = stackDepth,
      maxNodes = 1024,
      maxTriangles = 4096,
      maxLeafSize = 8,
      layout = layout
    )

  /** One input: the ray, where it comes from, and the node's answer. */
  final case class In(tok: Token, fromLeaf: Boolean, occluded: Boolean, hits: Seq[(Boolean, Long)], node: NodeView)

  private def pokeToken(t: TraversalToken, tok: Token): Unit = {
    t.rayId.poke(tok.rayId.U)
    t.nodeIdx.poke(tok.nodeIdx.U)
    t.sp.poke(tok.sp.U)
    for (a <- 0 until 3) t.dirNeg(a).poke(tok.dirNeg(a).B)
    t.shadow.poke(tok.shadow.B)
    t.errors.poke(tok.errors.U)
  }

  /** A ray back from a leaf goes to the leaf-return lane, a box result to the box-result lane. */
  private def poke(dut: ResolvedControl, cfg: AccelConfig, in: In): Unit =
    if (in.fromLeaf) {
      dut.io.ret.valid.poke(true.B)
      pokeToken(dut.io.ret.bits.token, in.tok)
      dut.io.ret.bits.occluded.poke(in.occluded.B)
    } else pokeBox(dut, cfg, in)

  private def pokeBox(dut: ResolvedControl, cfg: AccelConfig, in: In): Unit = {
    val b = dut.io.in.bits
    dut.io.in.valid.poke(true.B)
    pokeToken(b.token, in.tok)
    for (((hit, _), i) <- in.hits.zipWithIndex) b.hit(i).poke(hit.B)
    val keys = in.hits.map { case (_, near) => FpOrder.keyOf(cfg.boxFloat, BigInt(near)) }
    for ((o, n) <- TraversalControl.orderOf(keys).zipWithIndex) b.order(n).poke(o.B)
    for ((r, i) <- in.node.refs.zipWithIndex) {
      b.refs(i).isLeaf.poke(r.isLeaf.B); b.refs(i).index.poke(r.index.U); b.refs(i).count.poke(r.count.U)
    }
    b.axis.poke(in.node.axis.U)
    b.nodeErrors.poke(in.node.errors.U)
  }

  private def golden(cfg: AccelConfig, stack: mutable.ArrayBuffer[Ref], in: In): Out =
    ControlGolden.step(
      cfg.layout,
      cfg.stackDepth,
      stack,
      in.tok,
      in.fromLeaf,
      in.occluded,
      in.hits.map { case (h, near) => SlotHit(h, FpOrder.keyOf(cfg.boxFloat, BigInt(near))) },
      in.node
    )

  private def lane(dut: ResolvedControl, fromLeaf: Boolean): Valid[ControlOut] =
    if (fromLeaf) dut.io.retOut else dut.io.out
  private def latencyOf(dut: ResolvedControl, fromLeaf: Boolean): Int = if (fromLeaf) 1 else dut.latency
  private def idle(dut: ResolvedControl): Unit = { dut.io.in.valid.poke(false.B); dut.io.ret.valid.poke(false.B) }

  private def expectOut(port: Valid[ControlOut], e: Out, what: String): Unit = {
    val o = port.bits
    port.valid.expect(true.B, what)
    val state = o.state.peek()
    val expectedState = e.state match {
      case Traverse => TraversalState.Traverse
      case Leaf     => TraversalState.Leaf
      case GoBack   => TraversalState.GoBack
      case Done     => TraversalState.Done
    }
    assert(state == expectedState, s"$what: state $state, expected ${e.state}")
    o.token.rayId.expect(e.token.rayId.U, what)
    o.token.sp.expect(e.token.sp.U, s"$what: sp")
    o.token.errors.expect(e.token.errors.U, s"$what: errors ${ErrorFlags.describe(o.token.errors.peek().litValue)}")
    if (e.state == Traverse || e.state == GoBack) o.token.nodeIdx.expect(e.token.nodeIdx.U, s"$what: next node")
    if (e.state == Leaf) {
      o.leafFirst.expect(e.leafFirst.U, s"$what: leaf first")
      o.leafCount.expect(e.leafCount.U, s"$what: leaf count")
    }
  }

  /** Sends `ins` back to back (one per cycle, each to its lane), checking each
    * output its lane's latency later, and no output on a lane with nothing due.
    */
  private def run(
      dut: ResolvedControl,
      cfg: AccelConfig,
      stacks: Int => mutable.ArrayBuffer[Ref],
      ins: Seq[(In, String)]
  ): Seq[Out] = {
    val due = Map(false -> mutable.Queue.empty[(Int, Out, String)], true -> mutable.Queue.empty[(Int, Out, String)])
    val outs = mutable.ArrayBuffer.empty[Out]
    var cycle = 0
    for (in <- ins.map(Some(_)) ++ Seq.fill(dut.latency)(None)) {
      idle(dut)
      for ((i, w) <- in) {
        val e = golden(cfg, stacks(i.tok.rayId), i)
        poke(dut, cfg, i); outs += e; due(i.fromLeaf).enqueue((cycle + latencyOf(dut, i.fromLeaf), e, w))
      }
      dut.clock.step(); cycle += 1
      for ((fromLeaf, q) <- due) {
        if (q.headOption.exists(_._1 == cycle)) { val (_, e, w) = q.dequeue(); expectOut(lane(dut, fromLeaf), e, w) }
        else lane(dut, fromLeaf).valid.expect(
          false.B,
          s"cycle $cycle: nothing due on the ${if (fromLeaf) "leaf-return" else "box-result"} lane"
        )
      }
    }
    outs.toSeq
  }

  private val f = (x: Float) => java.lang.Float.floatToRawIntBits(x).toLong & 0xffffffffL
  private val none = (k: Int) => NodeView(IndexedSeq.fill(k)(Ref(isLeaf = false, 0, 0)), 0, 0)

  it should "visit a wide node's hit children nearest first, ties to the lower slot, and pop the rest in order" in {
    val cfg = cfgOf(BvhLayout.Wide(4), stackDepth = 6)
    test(new ResolvedControl(cfg)).withAnnotations(Backends.treadle) { dut =>
      val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
      // Slots: 0 inner 10 at 5.0, 1 leaf (100, 3) at -2.0 (origin inside), 2 inner 30 at -2.0 (a tie), 3 missed.
      val node = NodeView(IndexedSeq(Ref(false, 10, 0), Ref(true, 100, 3), Ref(false, 30, 0), Ref(false, 40, 0)), 0, 0)
      val hits = Seq(true -> f(5f), true -> f(-2f), true -> f(-2f), false -> f(1f))
      val t0 = Token(3, 0, 0, Seq(false, false, false), shadow = false, 0)
      val o1 = run(dut, cfg, stacks(_), Seq(In(t0, fromLeaf = false, occluded = false, hits, node) -> "root"))
      assert(
        o1.head == Out(Leaf, t0.copy(sp = 2), 100, 3),
        s"nearest is the leaf in slot 1 (tie with slot 2): ${o1.head}"
      )
      assert(stacks(3) == Seq(Ref(false, 10, 0), Ref(false, 30, 0)), s"pushed farthest first: ${stacks(3)}")
      val back = In(o1.head.token, fromLeaf = true, occluded = false, Seq.fill(4)(false -> 0L), none(4))
      val o2 = run(dut, cfg, stacks(_), Seq(back -> "back from the leaf"))
      assert(o2.head.state == GoBack && o2.head.token.nodeIdx == 30 && o2.head.token.sp == 1, s"${o2.head}")
      val miss = In(o2.head.token, fromLeaf = false, occluded = false, Seq.fill(4)(false -> 0L), node)
      val o3 = run(dut, cfg, stacks(_), Seq(miss -> "node 30 missed"))
      assert(o3.head.state == GoBack && o3.head.token.nodeIdx == 10 && o3.head.token.sp == 0, s"${o3.head}")
      val o4 = run(dut, cfg, stacks(_), Seq(miss.copy(tok = o3.head.token) -> "node 10 missed"))
      assert(o4.head.state == Done && o4.head.token.errors == 0, s"${o4.head}")
    }
  }

  it should "pop a leaf entry straight to LEAF, without a node fetch" in {
    val cfg = cfgOf(BvhLayout.Wide(2))
    test(new ResolvedControl(cfg)).withAnnotations(Backends.treadle) { dut =>
      val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
      val node = NodeView(IndexedSeq(Ref(true, 7, 2), Ref(true, 9, 1)), 0, 0)
      val t0 = Token(1, 4, 0, Seq(true, true, true), shadow = true, 0)
      val o1 =
        run(dut, cfg, stacks(_), Seq(In(t0, false, false, Seq(true -> f(3f), true -> f(1f)), node) -> "two leaves"))
      assert(o1.head == Out(Leaf, t0.copy(sp = 1), 9, 1), s"${o1.head}")
      val o2 =
        run(dut, cfg, stacks(_), Seq(In(o1.head.token, true, false, Seq.fill(2)(false -> 0L), none(2)) -> "back"))
      assert(o2.head == Out(Leaf, t0, 7, 2), s"the popped leaf: ${o2.head}")
      val o3 =
        run(dut, cfg, stacks(_), Seq(In(o2.head.token, true, true, Seq.fill(2)(false -> 0L), none(2)) -> "occluded"))
      assert(o3.head.state == Done, s"an occluded shadow ray is done: ${o3.head}")
    }
  }

  // Quantized layouts decide as their wide layouts do (the node decoder differs, not the control).
  for (layout <- BvhLayout.all.filterNot(_.quantized)) {
    it should s"end a ray with StackOverflow instead of dropping a subtree, and stop on errors (layout ${layout.name})" in {
      val cfg = cfgOf(layout, stackDepth = 8)
      test(new ResolvedControl(cfg)).withAnnotations(Backends.treadle) { dut =>
        val k = cfg.boxLanes
        val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
        val node = NodeView(IndexedSeq.tabulate(k)(i => Ref(false, 20 + i, 0)), 1, 0)
        val hits = Seq.tabulate(k)(i => true -> f(i.toFloat))
        // Fill the stack to the brim, then one more decision that pushes.
        val pushes = layout.maxPushes
        val sp = cfg.stackDepth - pushes + 1
        stacks(1) ++= Seq.fill(sp)(Ref(false, 5, 0))
        val full = Token(1, 9, sp, Seq(false, false, false), shadow = false, 0)
        val o = run(dut, cfg, stacks(_), Seq(In(full, false, false, hits, node) -> "push past the stack"))
        assert(o.head.state == Done && o.head.token.errors == (1 << ErrorFlags.StackOverflow), s"${o.head}")
        val bad = node.copy(errors = 1 << ErrorFlags.IndexOverflow)
        val ok = Token(2, 9, 0, Seq(false, false, false), shadow = true, 0)
        val o2 = run(dut, cfg, stacks(_), Seq(In(ok, false, false, hits, bad) -> "node with an error"))
        assert(o2.head.state == Done && o2.head.token.errors == (1 << ErrorFlags.IndexOverflow), s"${o2.head}")
      }
    }

    it should s"match the golden model on random traffic from interleaved rays (layout ${layout.name})" in Seeded(
      s"TraversalControl.random.${layout.name}"
    ) { rnd =>
      val cfg = cfgOf(layout, stackDepth = 7, ids = 16)
      val k = cfg.boxLanes
      // Verilator for the wide layouts: treadle takes minutes on K(K-1)/2 key comparators.
      test(new ResolvedControl(cfg)).withAnnotations(if (k > 2) Backends.verilator else Backends.treadle) { dut =>
        val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
        def fresh(i: Int) = Token(i, rnd.nextInt(1000), 0, Seq.fill(3)(rnd.nextBoolean()), rnd.nextBoolean(), 0)
        val toks = Array.tabulate(cfg.numRayIds)(fresh)
        val lastState = Array.fill[State](cfg.numRayIds)(Traverse)
        val busyUntil = Array.fill(cfg.numRayIds)(-1)
        val due = Map(false -> mutable.Queue.empty[(Int, Out, String)], true -> mutable.Queue.empty[(Int, Out, String)])
        val seen = mutable.Map.empty[State, Int].withDefaultValue(0)
        // A few distinct distances, so ties are common.
        val nears = Seq(f(-1f), f(0f), f(-0f), f(0.5f), f(2f), f(2f), f(7.25f), f(Float.NegativeInfinity))
        for (cycle <- 0 until 3000) {
          idle(dut)
          // Each lane may take a ray this cycle: one back from a leaf, one with a
          // box result. A ray is never in the unit twice: only rays whose last
          // input came out a cycle ago or more are eligible.
          for (fromLeaf <- Seq(true, false)) {
            val free = (0 until cfg.numRayIds).filter(i => busyUntil(i) < cycle && (lastState(i) == Leaf) == fromLeaf)
            if (free.nonEmpty && rnd.nextInt(5) != 0) {
              val id = free(rnd.nextInt(free.size))
              val tok = toks(id)
              val occluded = fromLeaf && tok.shadow && rnd.nextInt(4) == 0
              val used = if (layout == BvhLayout.Nori) 1 else 1 + rnd.nextInt(k)
              val refs = IndexedSeq.tabulate(k)(_ =>
                if (rnd.nextInt(3) == 0) Ref(isLeaf = true, rnd.nextInt(4000), rnd.nextInt(9))
                else Ref(isLeaf = false, rnd.nextInt(1000), 0)
              )
              val node = NodeView(refs, rnd.nextInt(3), if (rnd.nextInt(200) == 0) 1 << ErrorFlags.IndexOverflow else 0)
              val hits = Seq.tabulate(k)(i => (i < used && rnd.nextInt(3) != 0, nears(rnd.nextInt(nears.size))))
              val in = In(tok, fromLeaf, occluded, hits, node)
              val e = golden(cfg, stacks(id), in)
              poke(dut, cfg, in)
              toks(id) = if (e.state == Done) { stacks(id).clear(); fresh(id) }
              else e.token
              lastState(id) = if (e.state == Done) Traverse else e.state
              val lat = latencyOf(dut, fromLeaf)
              // Back no sooner than a cycle after its output (Traversal's lane register at least): the stack
              // writes a push the cycle after the decision.
              busyUntil(id) = cycle + lat
              seen(e.state) += 1
              due(fromLeaf).enqueue((
                cycle + lat,
                e,
                s"cycle $cycle ray $id (${if (fromLeaf) "leaf return" else "box result"})"
              ))
            }
          }
          dut.clock.step()
          for ((fromLeaf, q) <- due) {
            if (q.headOption.exists(_._1 == cycle + 1)) {
              val (_, e, w) = q.dequeue(); expectOut(lane(dut, fromLeaf), e, w)
            } else lane(dut, fromLeaf).valid.expect(false.B, s"cycle ${cycle + 1}: nothing due on this lane")
          }
        }
        assert(Seq(Traverse, Leaf, GoBack, Done).forall(seen(_) > 100), s"state coverage too thin: $seen")
      }
    }
  }

  it should "pick the near child by the split axis in the nori layout" in {
    val cfg = cfgOf(BvhLayout.Nori)
    test(new ResolvedControl(cfg)).withAnnotations(Backends.treadle) { dut =>
      val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
      // Node 4: inner, split axis 1, right child 9. Ray A runs -y: right first; ray B +y: left (5) first.
      val node = NodeView(IndexedSeq(Ref(false, 9, 0)), 1, 0)
      val a = Token(0, 4, 0, Seq(false, true, false), shadow = false, 0)
      val b = Token(1, 4, 0, Seq(true, false, true), shadow = false, 0)
      val o = run(
        dut,
        cfg,
        stacks(_),
        Seq(In(a, false, false, Seq(true -> 0L), node) -> "A", In(b, false, false, Seq(true -> 0L), node) -> "B")
      )
      assert(o(0).token.nodeIdx == 9 && stacks(0) == Seq(Ref(false, 5, 0)), s"A: ${o(0)} ${stacks(0)}")
      assert(o(1).token.nodeIdx == 5 && stacks(1) == Seq(Ref(false, 9, 0)), s"B: ${o(1)} ${stacks(1)}")
    }
  }
}
