package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.fp.FpOrder
import rtaccel.{AccelConfig, ErrorFlags}
import rtaccel.bvh.{BvhLayout, ChildRef}

/** Where a ray goes after TraversalControl. TRAVERSE and GOBACK both lead to
  * a node fetch (the nearest hit child, or the node popped off the stack);
  * they are kept apart for the performance counters. LEAF hands a triangle
  * range to LeafIntersect, whether it was the nearest child or popped.
  */
object TraversalState extends ChiselEnum {
  val Traverse, Leaf, GoBack, Done = Value
}

/** A ray back from LeafIntersect, to the leaf-return lane. */
class ReturnIn(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)

  /** A shadow ray found an occluder, so it is finished. */
  val occluded = Bool()
}

/** A box result, to the box-result lane. */
class ControlIn(cfg: AccelConfig) extends Bundle {
  val token = new TraversalToken(cfg)

  /** BboxIntersect's answer for each slot of node `token.nodeIdx`. */
  val hit = Vec(cfg.boxLanes, Bool())

  /** The children's entry order, decided by the box stage beside its hits: per pair (j, i), j < i, of
    * [[TraversalControl.pairs]], child j's entry distance orders at or before child i's.
    */
  val order = Vec(TraversalControl.pairs(cfg.boxLanes).size, Bool())

  /** Where each slot leads (nori: the node itself). */
  val refs = Vec(cfg.boxLanes, new ChildRef(cfg))

  /** Nori layout: the node's split axis. */
  val axis = UInt(2.W)

  /** Decode errors of the node's used slots. */
  val nodeErrors = ErrorFlags()
}

class ControlOut(cfg: AccelConfig) extends Bundle {
  val state = TraversalState()

  /** Updated token: `nodeIdx` is the node to fetch next (TRAVERSE/GOBACK). */
  val token = new TraversalToken(cfg)
  val leafFirst = UInt(cfg.triIndexBits.W)
  val leafCount = UInt(cfg.leafCountBits.W)
}

/** Two traversal decisions per cycle, one per lane (docs/architecture.md;
  * its Scala twin is ControlGolden): the box-result lane decides for a ray
  * whose node was just tested, the leaf-return lane for a ray back from a
  * leaf, which can only pop. A separate lane for leaf returns lifts the bound
  * a single lane set at one decision per node visit plus one per leaf
  * (Cornell box, 4-wide: 5.0 decisions per ray, 1.85 of them leaf returns).
  *  - some child box hit: the nearest hit child is next: TRAVERSE to it (an
  *    inner node) or LEAF (its triangles); the other hit children are pushed,
  *    farthest first, so the next nearest is on top;
  *  - no hit, or back from a leaf: pop; a popped inner node is GOBACK (fetch
  *    it), a popped leaf is LEAF; DONE when the stack is empty;
  *  - any error flag: DONE, so the ray returns with its flag set.
  * Pushes that would pass `stackDepth` set StackOverflow and end the ray: no
  * subtree is ever dropped silently.
  *
  * Nearest: in the nori layout, the near child by the ray's direction along
  * the split axis (the node holds one box, its own); in a wide layout, the
  * hit children in order of entry distance, ties to the lower slot, a total
  * order, so the golden model stays bit-exact.
  *
  * Pipeline (box-result lane): wide layouts rank the children in a first
  * cycle (a popcount per child of the pairs' order, which the box stage
  * decided; beside it the push count, the stack-overflow test and the error
  * flags); then the decision and the stack access; the popped value
  * (synchronous read) leaves beside the decision the cycle after, and the
  * consumer combines them after its register ([[TraversalControl.resolve]]).
  * The leaf-return lane decides in its input cycle and outputs the next. A
  * ray is never in this unit twice at once, nor back the cycle after its
  * output, so no stack hazard.
  */
class TraversalControl(cfg: AccelConfig) extends Module {
  val io = IO(new Bundle {
    val in = Flipped(Valid(new ControlIn(cfg)))
    val out = Valid(new Decided(cfg))

    /** The leaf-return lane: one ray back from a leaf per cycle, out the next cycle. */
    val ret = Flipped(Valid(new ReturnIn(cfg)))
    val retOut = Valid(new Decided(cfg))

    /** Rays in its pipeline registers (RtAccel's ray_conservation assertion). */
    val held = Output(UInt(2.W))
  })
  override def desiredName = s"TraversalControl_k${cfg.boxLanes}_n${cfg.numRayIds}_d${cfg.stackDepth}"

  private val k = cfg.boxLanes
  private val pushes = cfg.layout.maxPushes
  private val rankBits = log2Ceil(k).max(1)
  val latency: Int = if (cfg.layout == BvhLayout.Nori) 1 else 2

  // ---- Rank stage (wide): rank(i) = hit children before child i ----
  // What depends only on which children were hit (not on their order) is
  // decided here too, beside the ranks' counts: the push
  // count, the overflow test and the error flags then leave a register rather
  // than run into the stack's write address in the decision cycle (Fmax,
  // docs/fmax.md). Same logic, one register earlier; the nori layout has no
  // rank stage and computes it in its one cycle as before.
  class Ranked extends Bundle {
    val in = new ControlIn(cfg)
    val rank = Vec(k, UInt(rankBits.W))

    /** Hit children after child i in entry order: hits - 1 - rank(i) for a hit child, counted beside the rank. */
    val after = Vec(k, UInt(rankBits.W))
    val hits = UInt(log2Ceil(k + 1).W)

    /** Some child box was hit: there is a next child. */
    val chosenOk = Bool()
    val pushCount = UInt(log2Ceil(pushes + 1).W)

    /** The token's, the node's and StackOverflow (pushes past stackDepth). */
    val errors = ErrorFlags()

    /** DONE: an error, or no hit and an empty stack. */
    val finished = Bool()
  }
  private def rank(in: ControlIn): Ranked = {
    val r = Wire(new Ranked)
    r.in := in
    // The pairs' order comes from the box stage (TraversalControl.order); j after i is the negation of i's pair.
    val pairLe = TraversalControl.pairs(k).zip(in.order).toMap
    for (i <- 0 until k) {
      val isBefore = for (j <- 0 until k if j != i) yield (if (j < i) pairLe((j, i)) else !pairLe((i, j)))
      val others = (0 until k).filter(_ != i).map(in.hit(_))
      r.rank(i) := PopCount(others.zip(isBefore).map { case (h, b) => h && b })
      // The order is total, so every other hit child is before or after i.
      r.after(i) := PopCount(others.zip(isBefore).map { case (h, b) => h && !b })
    }
    r.hits := PopCount(in.hit)
    val overflow = cfg.layout match {
      case BvhLayout.Nori =>
        r.chosenOk := in.hit(0)
        r.pushCount := (in.hit(0) && !in.refs(0).isLeaf).asUInt
        r.chosenOk && (in.token.sp +& r.pushCount > cfg.stackDepth.U)
      case _: BvhLayout.Wide =>
        r.chosenOk := in.hit.asUInt.orR
        r.pushCount := Mux(r.chosenOk, r.hits - 1.U, 0.U)
        // The overflow test sp + (n - 1) > stackDepth, for n hits, is
        // sp > stackDepth + 1 - n: one compare of sp with a constant per
        // count, made from the token beside the hit count, the hits then
        // only choosing among them ("at least n hits" as plain logic, no
        // adder; chosenOk an OR, not the count). Through the popcount, the
        // decrement and the add, the test was Traversal's longest path
        // (docs/fmax.md). A larger count only lowers the bound, so OR-ing
        // the tests of every count up to the actual one is the actual one's.
        val atLeast = in.hit.foldLeft(Seq(true.B)) { (c, h) =>
          (0 to c.size).map(n => if (n == 0) true.B else if (n == c.size) c(n - 1) && h else c(n) || (c(n - 1) && h))
        }
        def spOver(n: Int): Bool = if (cfg.stackDepth + 1 - n < 0) true.B else in.token.sp > (cfg.stackDepth + 1 - n).U
        (1 to k).map(n => atLeast(n) && spOver(n)).reduce(_ || _)
    }
    r.errors := in.token.errors | in.nodeErrors | Mux(overflow, ErrorFlags.bit(ErrorFlags.StackOverflow), 0.U)
    r.finished := r.errors.orR || (!r.chosenOk && in.token.sp === 0.U)
    r
  }
  private val (valid, d) = cfg.layout match {
    case BvhLayout.Nori => (io.in.valid, rank(io.in.bits))
    case _              => (RegNext(io.in.valid, false.B), RegEnable(rank(io.in.bits), io.in.valid))
  }

  // ---- Decision: the next child and the pushes ----
  private val in = d.in
  private val tok = in.token
  private val chosen = Wire(new ChildRef(cfg))
  private val chosenOk = d.chosenOk
  private val pushCount = d.pushCount
  private val pushVals = Wire(Vec(pushes, new ChildRef(cfg)))
  cfg.layout match {
    case BvhLayout.Nori =>
      // Near child first: left (= this node + 1) unless the ray runs toward
      // negative coordinates along the split axis.
      val self = in.refs(0)
      val left = tok.nodeIdx + 1.U
      val rightNear = tok.dirNeg(in.axis)
      def inner(idx: UInt): ChildRef = {
        val c = Wire(new ChildRef(cfg)); c := DontCare
        c.isLeaf := false.B; c.index := idx; c.count := 0.U
        c
      }
      chosen := Mux(self.isLeaf, self, inner(Mux(rightNear, self.index, left)))
      pushVals(0) := inner(Mux(rightNear, left, self.index))
    case _: BvhLayout.Wide =>
      chosen := Mux1H(in.hit.zip(d.rank).map { case (h, r) => h && r === 0.U }, in.refs)
      // Port p (slot sp + p) takes the child ranked hits-1-p, i.e. with p hit children after it: farthest
      // lowest. Selected by `after`, a compare with a constant: no subtraction before the stack's write data.
      for (p <- 0 until pushes)
        pushVals(p) := Mux1H(in.hit.zip(d.after).map { case (h, a) => h && a === p.U }, in.refs)
  }

  private val errors = d.errors
  private val finished = d.finished

  private val state = Wire(TraversalState())
  state := Mux(
    finished,
    TraversalState.Done,
    Mux(!chosenOk, TraversalState.GoBack, Mux(chosen.isLeaf, TraversalState.Leaf, TraversalState.Traverse))
  )

  private val stack = Module(new RayStack(cfg))
  private val descend = valid && !finished && chosenOk
  stack.io.rayId := tok.rayId
  stack.io.sp := tok.sp
  stack.io.pushCount := Mux(descend, pushCount, 0.U)
  stack.io.pushVals := pushVals
  stack.io.pop := valid && state === TraversalState.GoBack

  private val next = Wire(new ControlOut(cfg))
  next.state := state
  next.token := tok
  next.token.errors := errors
  next.token.sp := Mux(finished, tok.sp, Mux(chosenOk, tok.sp + pushCount, tok.sp - 1.U))
  next.token.nodeIdx := Mux(state === TraversalState.Traverse, chosen.index(cfg.nodeIndexBits - 1, 0), tok.nodeIdx)
  next.leafFirst := chosen.index(cfg.triIndexBits - 1, 0)
  next.leafCount := chosen.count

  io.out := decided(valid, next, stack.io.popRead)

  // ---- Leaf-return lane: pop, or DONE (an error, an occluder, an empty stack) ----
  private val r = io.ret.bits
  private val retDone = r.token.errors.orR || r.occluded || r.token.sp === 0.U
  stack.io.rayIdB := r.token.rayId
  stack.io.spB := r.token.sp
  stack.io.popB := io.ret.valid && !retDone
  private val retNext = Wire(new ControlOut(cfg))
  retNext := DontCare
  retNext.state := Mux(retDone, TraversalState.Done, TraversalState.GoBack)
  retNext.token := r.token
  retNext.token.sp := Mux(retDone, r.token.sp, r.token.sp - 1.U)
  io.retOut := decided(io.ret.valid, retNext, stack.io.popReadB)
  // The nori layout has no rank register: its input is not held here.
  private val ranked = if (cfg.layout == BvhLayout.Nori) false.B else valid
  io.held := ranked +& io.out.valid +& io.retOut.valid

  /** A lane's output, a cycle after its decision: the decision and the popped entry (the stack's synchronous
    * read), not yet combined ([[TraversalControl.resolve]]): the consumer registers both first, so that the
    * stack's read is not one path with the combination and what follows it (docs/fmax.md).
    */
  private def decided(valid: Bool, next: ControlOut, popped: StackRead): Valid[Decided] = {
    val o = Wire(Valid(new Decided(cfg)))
    o.valid := RegNext(valid, false.B)
    o.bits.next := RegEnable(next, valid)
    o.bits.popped := popped
    o
  }
}

/** A lane's decision and the stack read it popped (meaningful for GOBACK), before [[TraversalControl.resolve]]:
  * every bank's output, so that the bank select too comes after the consumer's register (selected before it, the
  * block RAM's output ran through the select into the register, 5.16 ns, docs/fmax.md).
  */
class Decided(cfg: AccelConfig) extends Bundle {
  val next = new ControlOut(cfg)
  val popped = new StackRead(cfg)
}

object TraversalControl {

  /** The lane's output: a popped entry is an inner node to fetch (GOBACK) or a leaf to test (LEAF). */
  def resolve(cfg: AccelConfig, d: Decided): ControlOut = {
    val o = WireInit(d.next)
    val popped = d.popped.value
    when(d.next.state === TraversalState.GoBack) {
      when(popped.isLeaf) {
        o.state := TraversalState.Leaf
        o.leafFirst := popped.index(cfg.triIndexBits - 1, 0)
        o.leafCount := popped.count
      }.otherwise {
        o.token.nodeIdx := popped.index(cfg.nodeIndexBits - 1, 0)
      }
    }
    o
  }

  /** The pairs (j, i), j < i, of `k` children whose entry order the box stage decides, in [[ControlIn]]'s order. */
  def pairs(k: Int): Seq[(Int, Int)] = for (j <- 0 until k; i <- j + 1 until k) yield (j, i)

  /** Per pair (j, i): child j's entry distance `near(j)` orders at or before child i's, ties to the lower slot.
    * A float's key (FpOrder, compared by sign and magnitude), or with grid box tests a two's-complement integer's
    * with its sign bit flipped. The box stage registers it beside its hits: the compares and the ranks behind
    * them were one path in the rank stage (docs/fmax.md).
    */
  def order(cfg: AccelConfig, near: Seq[UInt]): Vec[Bool] = {
    def flipped(x: UInt): UInt = Cat(!x(cfg.nearBits - 1), x(cfg.nearBits - 2, 0))
    val ps = pairs(cfg.boxLanes)
    val o = Wire(Vec(ps.size, Bool())) // empty with one child (the nori layout)
    for (((j, i), n) <- ps.zipWithIndex)
      o(n) := (if (cfg.gridBox) flipped(near(j)) <= flipped(near(i)) else FpOrder.keyLe(cfg.boxFloat, near(j), near(i)))
    o
  }

  /** [[order]]'s bits from the children's unsigned keys (FpOrder.keyOf), for models and specs. */
  def orderOf(keys: Seq[BigInt]): Seq[Boolean] = pairs(keys.size).map { case (j, i) => keys(j) <= keys(i) }
}
