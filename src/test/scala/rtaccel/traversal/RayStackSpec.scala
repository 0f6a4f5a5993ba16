package rtaccel.traversal

import chisel3._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.AccelConfig
import rtaccel.bvh.{BvhLayout, ChildRef}
import rtaccel.sim.Backends
import rtaccel.testutil.Seeded

import scala.collection.mutable

/** RayStack alone, against one Scala stack per ray: port A pushes up to
  * `maxPushes` entries or pops one, port B pops, on two different rays each
  * cycle, neither at a port the cycle before (TraversalControl's contract), with seeded random choices and idle
  * cycles. Every popped value is checked the cycle after its pop: nothing
  * pushed is lost, overwritten by another ray or bank, or read twice.
  */
class RayStackSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RayStack"

  private final case class Ref(isLeaf: Boolean, index: Int, count: Int)

  // Rows per ray: depth 9 gives 9 (Nori) and 3 (4-wide), a row address with an adder; depth 16 gives 16 and 4,
  // the ray ID beside the row bits. 8-wide (8 banks) has 2 rows at both.
  for (layout <- Seq(BvhLayout.Nori, BvhLayout.Wide(4), BvhLayout.Wide(8)); depth <- Seq(9, 16)) {
    it should s"return every pushed entry of every ray, in LIFO order, on both ports (layout ${layout.name}, depth $depth)" in
      Seeded(s"RayStack.${layout.name}.d$depth") { rnd =>
        val cfg = AccelConfig(
          numRayIds = 6,
          stackDepth = depth,
          maxNodes = 256,
          maxTriangles = 256,
          maxLeafSize = 4,
          layout = layout
        )
        test(new RayStack(cfg)).withAnnotations(Backends.treadle) { dut =>
          val stacks = Array.fill(cfg.numRayIds)(mutable.ArrayBuffer.empty[Ref])
          def randomRef(): Ref =
            if (rnd.nextBoolean()) Ref(isLeaf = true, rnd.nextInt(cfg.maxTriangles), 1 + rnd.nextInt(cfg.maxLeafSize))
            else Ref(isLeaf = false, rnd.nextInt(cfg.maxNodes), 0)
          def expectRef(port: ChildRef, want: Ref, what: String): Unit = {
            port.isLeaf.expect(want.isLeaf.B, what)
            port.index.expect(want.index.U, what)
            if (want.isLeaf) port.count.expect(want.count.U, what)
          }
          var pendingA: Option[(Ref, String)] = None
          var pendingB: Option[(Ref, String)] = None
          var pushes, pops = 0
          var prev = Set.empty[Int]
          for (cycle <- 0 until 800) {
            pendingA.foreach { case (r, w) => expectRef(dut.io.popVal, r, w) }
            pendingB.foreach { case (r, w) => expectRef(dut.io.popValB, r, w) }
            pendingA = None; pendingB = None

            // Neither ray was at a port in the last cycle: a ray is back in TraversalControl only many cycles
            // after a decision, and a push is written the cycle after it is offered.
            val freeA = (0 until cfg.numRayIds).filterNot(prev.contains)
            val a = freeA(rnd.nextInt(freeA.size))
            val freeB = freeA.filter(_ != a)
            val b = freeB(rnd.nextInt(freeB.size))
            prev = Set(a, b)
            val sa = stacks(a); val sb = stacks(b)
            // Port A: push (more often while the stack is shallow), pop, or idle.
            val room = cfg.stackDepth - sa.size
            val n = if (room > 0 && rnd.nextInt(3) > 0) 1 + rnd.nextInt(room.min(layout.maxPushes)) else 0
            val popA = n == 0 && sa.nonEmpty && rnd.nextInt(4) > 0
            dut.io.rayId.poke(a.U)
            dut.io.sp.poke(sa.size.U)
            dut.io.pushCount.poke(n.U)
            val vals = Seq.fill(layout.maxPushes)(randomRef())
            for ((v, p) <- vals.zipWithIndex) {
              dut.io.pushVals(p).isLeaf.poke(v.isLeaf.B)
              dut.io.pushVals(p).index.poke(v.index.U)
              dut.io.pushVals(p).count.poke(v.count.U)
            }
            dut.io.pop.poke(popA.B)
            if (popA) pendingA = Some(sa.remove(sa.size - 1) -> s"cycle $cycle: port A pop of ray $a (slot ${sa.size})")
            sa ++= vals.take(n)
            pushes += n
            // Port B: pop a different ray, or idle.
            val popB = sb.nonEmpty && rnd.nextInt(3) > 0
            dut.io.rayIdB.poke(b.U)
            dut.io.spB.poke(sb.size.U)
            dut.io.popB.poke(popB.B)
            if (popB) pendingB = Some(sb.remove(sb.size - 1) -> s"cycle $cycle: port B pop of ray $b (slot ${sb.size})")
            pops += (if (popA) 1 else 0) + (if (popB) 1 else 0)
            dut.clock.step()
          }
          pendingA.foreach { case (r, w) => expectRef(dut.io.popVal, r, w) }
          pendingB.foreach { case (r, w) => expectRef(dut.io.popValB, r, w) }
          // Drain: every entry still held comes back, on alternating ports, after an idle cycle (the last pushes'
          // write).
          dut.io.pushCount.poke(0.U)
          dut.io.pop.poke(false.B); dut.io.popB.poke(false.B)
          dut.clock.step()
          for (ray <- 0 until cfg.numRayIds; s = stacks(ray); _ <- s.indices) {
            val port = if (s.size % 2 == 0) dut.io.popVal else dut.io.popValB
            dut.io.pop.poke((s.size % 2 == 0).B); dut.io.popB.poke((s.size % 2 == 1).B)
            dut.io.rayId.poke(ray.U); dut.io.sp.poke(s.size.U)
            dut.io.rayIdB.poke(ray.U); dut.io.spB.poke(s.size.U)
            val want = s.remove(s.size - 1)
            dut.clock.step()
            expectRef(port, want, s"drain of ray $ray, slot ${s.size}")
            pops += 1
          }
          assert(pushes == pops, s"pushed $pushes entries but popped $pops")
          assert(pushes > 250, s"only $pushes pushes: the random walk does not exercise the stack")
        }
      }
  }
}
