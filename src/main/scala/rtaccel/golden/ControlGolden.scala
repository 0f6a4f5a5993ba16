package rtaccel.golden

import rtaccel.ErrorFlags

/** Plain-Scala meaning of TraversalControl's decision, shared by its spec and
  * by the whole-traversal golden model, so both speak of the same order.
  */
object ControlGolden {
  sealed trait State
  case object Traverse extends State
  case object Leaf extends State
  case object GoBack extends State
  case object Done extends State

  final case class Links(isLeaf: Boolean, axis: Int, rightChild: Long, first: Long, count: Int, errors: Int)
  final case class Token(rayId: Int, nodeIdx: Long, sp: Int, dirNeg: Seq[Boolean], shadow: Boolean, errors: Int)
  final case class Out(state: State, token: Token, leafFirst: Long, leafCount: Int)

  /** One decision. `stack` is the ray's stack (index 0 = bottom), updated in place. */
  def step(stackDepth: Int, stack: scala.collection.mutable.ArrayBuffer[Long], tok: Token,
      fromLeaf: Boolean, occluded: Boolean, boxHit: Boolean, links: Links): Out = {
    require(stack.size == tok.sp, s"ray ${tok.rayId}: stack holds ${stack.size} entries but sp = ${tok.sp}")
    val errorsIn = tok.errors | (if (fromLeaf) 0 else links.errors)
    val descend = !fromLeaf && boxHit && !links.isLeaf
    val enterLeaf = !fromLeaf && boxHit && links.isLeaf
    val overflow = descend && tok.sp == stackDepth
    val errors = errorsIn | (if (overflow) 1 << ErrorFlags.StackOverflow else 0)
    val finished = errors != 0 || (fromLeaf && occluded) || (!descend && !enterLeaf && tok.sp == 0)
    val t = tok.copy(errors = errors)
    if (finished) Out(Done, t, links.first, links.count)
    else if (descend) {
      val left = tok.nodeIdx + 1
      val rightNear = tok.dirNeg(links.axis)
      val (near, far) = if (rightNear) (links.rightChild, left) else (left, links.rightChild)
      stack += far
      Out(Traverse, t.copy(nodeIdx = near, sp = tok.sp + 1), links.first, links.count)
    } else if (enterLeaf) Out(Leaf, t, links.first, links.count)
    else Out(GoBack, t.copy(nodeIdx = stack.remove(stack.size - 1), sp = tok.sp - 1), links.first, links.count)
  }
}
