package rtaccel.golden

import rtaccel.ErrorFlags
import rtaccel.bvh.BvhLayout

/** Plain-Scala meaning of TraversalControl's decision, shared by its spec and
  * by the whole-traversal golden model, so both speak of the same order.
  */
object ControlGolden {
  sealed trait State
  case object Traverse extends State
  case object Leaf extends State
  case object GoBack extends State
  case object Done extends State

  /** Where a child leads (an inner node, or a leaf's triangles); what a stack holds. */
  final case class Ref(isLeaf: Boolean, index: Long, count: Int)

  /** A node as decoded for `cfg`: each slot's reference (nori: the node
    * itself), the split axis (nori) and the decode errors of the used slots.
    */
  final case class NodeView(refs: IndexedSeq[Ref], axis: Int, errors: Int)

  /** BboxIntersect's answer for one slot: hit, and the entry distance's order key. */
  final case class SlotHit(hit: Boolean, nearKey: BigInt)
  final case class Token(rayId: Int, nodeIdx: Long, sp: Int, dirNeg: Seq[Boolean], shadow: Boolean, errors: Int)
  final case class Out(state: State, token: Token, leafFirst: Long, leafCount: Int)

  /** The hit children in visiting order: nearest first, ties to the lower slot. */
  def order(hits: Seq[SlotHit]): Seq[Int] =
    hits.indices.filter(hits(_).hit).sortBy(i => (hits(i).nearKey, i))

  /** One decision. `stack` is the ray's stack (index 0 = bottom), updated in
    * place. `hits` is ignored for a ray back from a leaf.
    */
  def step(
      layout: BvhLayout,
      stackDepth: Int,
      stack: scala.collection.mutable.ArrayBuffer[Ref],
      tok: Token,
      fromLeaf: Boolean,
      occluded: Boolean,
      hits: Seq[SlotHit],
      node: NodeView
  ): Out = {
    require(stack.size == tok.sp, s"ray ${tok.rayId}: stack holds ${stack.size} entries but sp = ${tok.sp}")
    val errorsIn = tok.errors | (if (fromLeaf) 0 else node.errors)
    // The child visited next, and the entries pushed (bottom first).
    val (chosen, pushes): (Option[Ref], Seq[Ref]) =
      if (fromLeaf) (None, Nil)
      else layout match {
        case BvhLayout.Nori =>
          val self = node.refs(0)
          if (!hits(0).hit) (None, Nil)
          else if (self.isLeaf) (Some(self), Nil)
          else {
            val left = Ref(isLeaf = false, tok.nodeIdx + 1, 0)
            val right = Ref(isLeaf = false, self.index, 0)
            if (tok.dirNeg(node.axis)) (Some(right), Seq(left)) else (Some(left), Seq(right))
          }
        case _: BvhLayout.Wide =>
          val o = order(hits).map(node.refs)
          (o.headOption, o.drop(1).reverse)
      }
    val overflow = chosen.isDefined && tok.sp + pushes.size > stackDepth
    val errors = errorsIn | (if (overflow) 1 << ErrorFlags.StackOverflow else 0)
    val finished = errors != 0 || (fromLeaf && occluded) || (chosen.isEmpty && tok.sp == 0)
    val t = tok.copy(errors = errors)
    if (finished) Out(Done, t, 0, 0)
    else chosen match {
      case Some(c) =>
        stack ++= pushes
        val moved = t.copy(sp = tok.sp + pushes.size)
        if (c.isLeaf) Out(Leaf, moved, c.index, c.count) else Out(Traverse, moved.copy(nodeIdx = c.index), 0, 0)
      case None =>
        val e = stack.remove(stack.size - 1)
        val popped = t.copy(sp = tok.sp - 1)
        if (e.isLeaf) Out(Leaf, popped, e.index, e.count) else Out(GoBack, popped.copy(nodeIdx = e.index), 0, 0)
    }
  }
}
