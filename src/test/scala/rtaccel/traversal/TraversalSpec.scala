package rtaccel.traversal

import chisel3._
import chisel3.util._
import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.golden.ControlGolden
import rtaccel.golden.ControlGolden._
import rtaccel.golden.TraversalGolden
import rtaccel.leaf.{LeafExit, LeafJob}
import rtaccel.scene.{MemoryImage, Records}
import rtaccel.testutil.Seeded
import rtaccel.AccelConfig
import rtaccel.bvh.{BvhLayout, BvhNode}
import rtaccel.sim.{Backends, FieldDatapath, SyntheticBvh}
import rtaccel.sim.mem.{Latency, MemPortHarness, MemoryParams, MemorySystemModel}

import scala.collection.mutable
import scala.util.Random

/** Traversal with a RayBuffer beside it (as in RtAccel), the root given as a raw record. */
class TraversalHarness(val cfg: AccelConfig) extends Module {
  private val dp = FieldDatapath
  val trav = Module(new Traversal(cfg, dp))
  private val rays = Module(new RayBuffer(cfg, dp.gen, readers = 1))
  val io = IO(new Bundle {
    val write = Flipped(Decoupled(new RayEntry(cfg, dp.gen)))
    val entry = Flipped(Decoupled(new TraversalToken(cfg)))
    val rootRecord = Input(UInt((cfg.layout.nodeBytes * 8).W))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val mem = chiselTypeOf(trav.io.mem)
    val leafOut = Decoupled(new LeafJob(cfg))
    val leafIn = Flipped(Decoupled(new LeafExit(cfg)))
    val done = Decoupled(new TraversalToken(cfg))
    val overflow = Output(Bool())
  })
  rays.io.enter <> io.write
  rays.io.update.valid := false.B
  rays.io.update.bits := DontCare
  rays.io.read(0) <> trav.io.rayRead
  trav.io.entry.valid := io.entry.valid
  trav.io.entry.bits.token := io.entry.bits
  trav.io.entry.bits.root := BvhNode.decode(cfg, io.rootRecord)
  io.entry.ready := trav.io.entry.ready
  trav.io.nodeBase := io.nodeBase
  io.mem <> trav.io.mem
  io.leafOut <> trav.io.leafOut
  trav.io.leafIn <> io.leafIn
  io.done <> trav.io.done
  io.overflow := trav.io.overflow
}

/** The Traversal top on its own: rays enter at the root, node fetches go to
  * the memory model (random latency, out of order, refusals), leaf jobs to a
  * scoreboard that answers them after a random delay. Every ray's sequence of
  * leaf jobs and its final token must be what ControlGolden's walk of the
  * same tree gives (no triangle hits here, so tmax stays), and each ray must
  * leave exactly once.
  */
class TraversalSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "Traversal"

  /** The leaf jobs and the final token of a ray whose leaves never hit. */
  private def walk(
      cfg: AccelConfig,
      img: MemoryImage,
      statics: Int,
      tmax: Long,
      tok0: Token
  ): (Seq[(Long, Int, Int)], Token) = {
    val stack = mutable.ArrayBuffer.empty[Ref]
    var tok = tok0
    var node = Records.node(img, 0)
    var fromLeaf = false
    val leaves = mutable.ArrayBuffer.empty[(Long, Int, Int)]
    var state: State = Traverse
    while (state != Done) {
      val (hits, view) = TraversalGolden.testNode(cfg, FieldDatapath.Golden, statics, BigInt(tmax), node)
      val out = ControlGolden.step(cfg.layout, cfg.stackDepth, stack, tok, fromLeaf, occluded = false, hits, view)
      tok = out.token; state = out.state; fromLeaf = false
      state match {
        case Traverse | GoBack => node = Records.node(img, tok.nodeIdx)
        case Leaf              => leaves += ((out.leafFirst, out.leafCount, tok.sp)); fromLeaf = true
        case Done              => ()
      }
    }
    (leaves.toSeq, tok)
  }

  for (layout <- Seq(BvhLayout.Nori, BvhLayout.Wide(4), BvhLayout.Wide(4, quantized = true))) {
    it should s"visit each ray's leaves in the golden order and finish it exactly once (layout ${layout.name})" in
      Seeded(s"Traversal.${layout.name}") { rnd =>
        val (img, stack) = layout match {
          case BvhLayout.Nori => (SyntheticBvh(new Random(rnd.nextLong()), maxDepth = 7, maxLeaf = 4), 5)
          case _ =>
            (SyntheticBvh(new Random(rnd.nextLong()), maxDepth = 4, maxLeaf = 4, layout = layout), 3 * layout.maxPushes)
        }
        val cfg = AccelConfig(
          numRayIds = 8,
          stackDepth = stack,
          maxNodes = 4096,
          maxTriangles = 4096,
          maxLeafSize = 4,
          layout = layout
        )
        test(new TraversalHarness(cfg)).withAnnotations(Backends.verilator) { dut =>
          dut.clock.setTimeout(0)
          val io = dut.io
          io.nodeBase.poke(img.nodeOffset.U)
          io.rootRecord.poke(img.readLE(img.nodeAddr(0), img.nodeBytes.toInt).U)
          val model = new MemorySystemModel(
            img,
            img.nodeBytes.toInt,
            MemoryParams(Latency.Uniform(1, 40), maxOutstanding = 6, seed = rnd.nextLong()),
            "node"
          )
          val mem = new MemPortHarness(io.mem, model, refuse = 0.2, rnd = new Random(rnd.nextLong()))
          final class Ray(val tok: Token, val leaves: Seq[(Long, Int, Int)], val last: Token) { var seen = 0 }
          val inside = mutable.Map.empty[Int, Ray]
          val leafWait = mutable.Queue.empty[(Int, Int, Boolean)] // (cycle due, ray, shadow) answers for the leaf side
          var started, finished, leafJobs, overflows = 0
          var phase: Option[(Int, Token)] = None // a ray written to the RayBuffer, entering next
          val total = 400
          for (cycle <- 0 until 60000 if finished < total) {
            // Enter: write the RayBuffer, then send the token (the order InitTraversal keeps).
            io.write.valid.poke(false.B); io.entry.valid.poke(false.B)
            phase match {
              case None if started < total && inside.size < cfg.numRayIds && rnd.nextBoolean() =>
                val id = (0 until cfg.numRayIds).find(i => !inside.contains(i)).get
                val statics = rnd.nextInt(1 << 16)
                val tmax = java.lang.Float.floatToRawIntBits((1 + rnd.nextInt(8)).toFloat).toLong
                val tok = Token(id, 0, 0, Seq.fill(3)(rnd.nextBoolean()), rnd.nextBoolean(), 0)
                val (leaves, last) = walk(cfg, img, statics, tmax, tok)
                inside(id) = new Ray(tok, leaves, last)
                io.write.valid.poke(true.B); io.write.bits.rayId.poke(id.U)
                io.write.bits.statics.poke(statics.U); io.write.bits.tmax.poke(tmax.U)
                phase = Some((cycle, tok)); started += 1
              case Some((at, tok)) if cycle > at =>
                io.entry.valid.poke(true.B)
                io.entry.bits.rayId.poke(tok.rayId.U); io.entry.bits.nodeIdx.poke(0.U); io.entry.bits.sp.poke(0.U)
                for (a <- 0 until 3) io.entry.bits.dirNeg(a).poke(tok.dirNeg(a).B)
                io.entry.bits.shadow.poke(tok.shadow.B); io.entry.bits.errors.poke(0.U)
                if (io.entry.ready.peek().litToBoolean) phase = None
              case _ => ()
            }
            // The leaf side: take jobs when it likes, answer them later (never occluded).
            io.leafOut.ready.poke(rnd.nextInt(3) != 0)
            if (io.leafOut.valid.peek().litToBoolean && io.leafOut.ready.peek().litToBoolean) {
              val j = io.leafOut.bits
              val id = j.token.rayId.peek().litValue.toInt
              val r = inside.getOrElse(id, fail(s"cycle $cycle: leaf job for ray $id, which is not inside"))
              val job =
                (j.first.peek().litValue.toLong, j.count.peek().litValue.toInt, j.token.sp.peek().litValue.toInt)
              assert(
                r.seen < r.leaves.size && r.leaves(r.seen) == job,
                s"cycle $cycle: ray $id's leaf job ${r.seen}: $job, golden ${r.leaves.lift(r.seen)}"
              )
              r.seen += 1; leafJobs += 1
              leafWait.enqueue((cycle + 1 + rnd.nextInt(15), id, r.tok.shadow))
            }
            val answer = leafWait.headOption.filter(_._1 <= cycle)
            io.leafIn.valid.poke(answer.isDefined.B)
            answer.foreach { case (_, id, shadow) =>
              val t = io.leafIn.bits.token
              val r = inside(id)
              // The token as it left for the leaf: sp after the pushes.
              t.rayId.poke(id.U); t.nodeIdx.poke(0.U); t.sp.poke(r.leaves(r.seen - 1)._3.U)
              for (a <- 0 until 3) t.dirNeg(a).poke(r.tok.dirNeg(a).B)
              t.shadow.poke(shadow.B); t.errors.poke(0.U)
              io.leafIn.bits.occluded.poke(false.B)
            }
            if (answer.isDefined && io.leafIn.ready.peek().litToBoolean) leafWait.dequeue()
            // Done: each ray once, after all its leaves, with the golden errors.
            io.done.ready.poke(rnd.nextInt(4) != 0)
            if (io.done.valid.peek().litToBoolean && io.done.ready.peek().litToBoolean) {
              val id = io.done.bits.rayId.peek().litValue.toInt
              val r = inside.remove(id).getOrElse(
                fail(s"cycle $cycle: ray $id finished, but it is not inside (lost or duplicated)")
              )
              assert(
                r.seen == r.leaves.size,
                s"cycle $cycle: ray $id finished after ${r.seen} of ${r.leaves.size} leaves"
              )
              io.done.bits.errors.expect(r.last.errors.U, s"ray $id: errors")
              if (r.last.errors != 0) overflows += 1
              finished += 1
            }
            io.overflow.expect(false.B)
            mem.drive()
            dut.clock.step(); mem.tick()
          }
          assert(finished == total, s"$finished of $total rays finished (inside: ${inside.keys})")
          assert(leafJobs > total / 2, s"only $leafJobs leaf jobs: the trees test little")
          info(s"$total rays, $leafJobs leaf jobs, $overflows stack overflows, ${model.stats.requests} node fetches")
        }
      }
  }
}
