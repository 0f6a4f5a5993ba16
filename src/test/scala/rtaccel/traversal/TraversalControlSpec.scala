package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.golden.ControlGolden
import rtaccel.golden.ControlGolden._
import rtaccel.testutil.{Backends, Seeded}
import rtaccel.{AccelConfig, ErrorFlags}

import scala.collection.mutable
import scala.util.Random

class TraversalControlSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "TraversalControl"

  private val cfg = AccelConfig(numRayIds = 4, stackDepth = 3, maxNodes = 1024, maxTriangles = 4096, maxLeafSize = 8)

  private def poke(dut: TraversalControl, tok: Token, fromLeaf: Boolean, occluded: Boolean, boxHit: Boolean, l: Links): Unit = {
    val in = dut.io.in.bits
    dut.io.in.valid.poke(true.B)
    in.token.rayId.poke(tok.rayId.U)
    in.token.nodeIdx.poke(tok.nodeIdx.U)
    in.token.sp.poke(tok.sp.U)
    for (a <- 0 until 3) in.token.dirNeg(a).poke(tok.dirNeg(a).B)
    in.token.shadow.poke(tok.shadow.B)
    in.token.errors.poke(tok.errors.U)
    in.fromLeaf.poke(fromLeaf.B)
    in.occluded.poke(occluded.B)
    in.boxHit.poke(boxHit.B)
    in.links.isLeaf.poke(l.isLeaf.B)
    in.links.axis.poke(l.axis.U)
    in.links.rightChild.poke(l.rightChild.U)
    in.links.first.poke(l.first.U)
    in.links.count.poke(l.count.U)
    in.links.errors.poke(l.errors.U)
  }

  private def expectOut(dut: TraversalControl, e: Out, what: String): Unit = {
    val o = dut.io.out.bits
    dut.io.out.valid.expect(true.B, what)
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

  private val inner = (axis: Int, right: Long) => Links(isLeaf = false, axis, right, 0, 0, 0)
  private val leaf  = (first: Long, count: Int) => Links(isLeaf = true, 0, 0, first, count, 0)
  private val none  = Links(isLeaf = false, 0, 0, 0, 0, 0)

  it should "walk a crafted tree: near child first, leaf, pop, done; stacks of interleaved rays kept apart" in {
    test(new TraversalControl(cfg)).withAnnotations(Backends.treadle) { dut =>
      // Tree: 0 = inner(axis 0, right 4); 1 = inner(axis 1, right 3); 2, 3 = leaves; 4 = leaf.
      // Ray A runs +x, -y; ray B runs -x, +y. They alternate cycle by cycle.
      val stacks = Map(0 -> mutable.ArrayBuffer.empty[Long], 3 -> mutable.ArrayBuffer.empty[Long])
      var a = Token(0, 0, 0, Seq(false, true, false), shadow = false, 0)
      var b = Token(3, 0, 0, Seq(true, false, false), shadow = false, 0)
      type Step = Token => (Boolean, Boolean, Links, State, Long)
      def send(steps: (String, Step)*): Unit =
        for ((which, f) <- steps) {
          val tok = if (which == "A") a else b
          val (fromLeaf, hit, l, st, node) = f(tok)
          val e = ControlGolden.step(cfg.stackDepth, stacks(tok.rayId), tok, fromLeaf, occluded = false, hit, l)
          assert(e.state == st && (st == Leaf || st == Done || e.token.nodeIdx == node), s"golden disagrees with the hand trace for $which: $e")
          poke(dut, tok, fromLeaf, occluded = false, hit, l)
          dut.clock.step()
          expectOut(dut, e, s"ray $which at node ${tok.nodeIdx}")
          if (which == "A") a = e.token else b = e.token
        }
      send("A" -> (_ => (false, true, inner(0, 4), Traverse, 1)), "B" -> (_ => (false, true, inner(0, 4), Traverse, 4))) // A pushes 4, B pushes 1
      send("A" -> (_ => (false, true, inner(1, 3), Traverse, 3)), "B" -> (_ => (false, true, leaf(7, 2), Leaf, 0)))     // A: -y => right (3) first, pushes 2
      send("A" -> (_ => (false, true, leaf(5, 1), Leaf, 0)), "B" -> (_ => (true, false, none, GoBack, 1)))              // B back from its leaf: pops 1
      send("A" -> (_ => (true, false, none, GoBack, 2)), "B" -> (_ => (false, false, inner(1, 3), Done, 0)))            // A pops 2; B misses 1 with an empty stack
      send("A" -> (_ => (false, false, leaf(0, 1), GoBack, 4)))                                                         // A misses 2: pops 4
      send("A" -> (_ => (false, false, leaf(0, 1), Done, 0)))                                                           // A misses 4: done
      assert(a.sp == 0 && b.sp == 0)
      dut.io.in.valid.poke(false.B)
      dut.clock.step()
      dut.io.out.valid.expect(false.B)
    }
  }

  it should "end a ray with StackOverflow instead of dropping a subtree, and stop on errors and occlusion" in {
    test(new TraversalControl(cfg)).withAnnotations(Backends.treadle) { dut =>
      val full = Token(1, 9, cfg.stackDepth, Seq(false, false, false), shadow = false, 0)
      poke(dut, full, fromLeaf = false, occluded = false, boxHit = true, inner(2, 20))
      dut.clock.step()
      expectOut(dut, Out(Done, full.copy(errors = 1 << ErrorFlags.StackOverflow), 0, 0), "push on a full stack")
      val ok = Token(2, 9, 1, Seq(false, false, false), shadow = true, 0)
      poke(dut, ok, fromLeaf = false, occluded = false, boxHit = true, inner(3, 20).copy(errors = 1 << ErrorFlags.IndexOverflow))
      dut.clock.step()
      expectOut(dut, Out(Done, ok.copy(errors = 1 << ErrorFlags.IndexOverflow), 0, 0), "node with an error")
      poke(dut, ok, fromLeaf = true, occluded = true, boxHit = false, none)
      dut.clock.step()
      expectOut(dut, Out(Done, ok, 0, 0), "occluded shadow ray back from its leaf")
    }
  }

  it should "match the golden model on random traffic from interleaved rays" in Seeded("TraversalControl.random") { rnd =>
    val big = AccelConfig(numRayIds = 16, stackDepth = 6, maxNodes = 1 << 12, maxTriangles = 1 << 12, maxLeafSize = 8)
    test(new TraversalControl(big)).withAnnotations(Backends.treadle) { dut =>
      val stacks = Array.fill(big.numRayIds)(mutable.ArrayBuffer.empty[Long])
      val toks = Array.tabulate(big.numRayIds)(i => Token(i, rnd.nextInt(1000), 0, Seq.fill(3)(rnd.nextBoolean()), rnd.nextBoolean(), 0))
      val lastState = Array.fill[State](big.numRayIds)(Traverse)
      var pending: Option[(Out, String)] = None
      val seen = mutable.Map.empty[State, Int].withDefaultValue(0)
      for (cycle <- 0 until 4000) {
        val fire = rnd.nextInt(5) != 0
        // The ray just sent is still inside the unit this cycle, so pick another.
        val busy = pending.map(_._1.token.rayId).toSet
        val id = Iterator.continually(rnd.nextInt(big.numRayIds)).find(i => !busy(i)).get
        val tok = toks(id)
        if (fire) {
          val fromLeaf = lastState(id) == Leaf
          val occluded = fromLeaf && tok.shadow && rnd.nextInt(4) == 0
          val l = if (rnd.nextBoolean()) Links(isLeaf = true, 0, 0, rnd.nextInt(4000), rnd.nextInt(9), 0)
                  else Links(isLeaf = false, rnd.nextInt(3), rnd.nextInt(4000), 0, 0, if (rnd.nextInt(200) == 0) 2 else 0)
          val hit = rnd.nextInt(3) != 0
          val e = ControlGolden.step(big.stackDepth, stacks(id), tok, fromLeaf, occluded, hit, l)
          poke(dut, tok, fromLeaf, occluded, hit, l)
          // A finished ray starts over as a fresh ray with the same ID.
          toks(id) = if (e.state == Done) { stacks(id).clear(); Token(id, rnd.nextInt(1000), 0, Seq.fill(3)(rnd.nextBoolean()), rnd.nextBoolean(), 0) } else e.token
          lastState(id) = if (e.state == Done) Traverse else e.state
          seen(e.state) += 1
          pending.foreach { case (p, w) => expectOut(dut, p, w) }
          dut.clock.step()
          pending = Some((e, s"cycle $cycle ray $id"))
        } else {
          dut.io.in.valid.poke(false.B)
          pending.foreach { case (p, w) => expectOut(dut, p, w) }
          dut.clock.step()
          pending = None
        }
        if (pending.isEmpty) dut.io.out.valid.expect(false.B, s"cycle $cycle: no input, no output")
      }
      assert(Seq(Traverse, Leaf, GoBack, Done).forall(seen(_) > 100), s"state coverage too thin: $seen")
    }
  }
}
