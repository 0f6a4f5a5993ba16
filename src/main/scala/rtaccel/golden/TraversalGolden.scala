package rtaccel.golden

import rtaccel.fp.{FloatFormat, FpOrder}
import rtaccel.scene.{MemoryImage, NodeRecord, Records, TriangleRecord}
import rtaccel.{AccelConfig, ErrorFlags}
import rtaccel.bvh.{BvhLayout, BvhNode, QuantNode}
import rtaccel.traversal.GridParams

import scala.collection.mutable

/** A ray as the host sends it (FP32 bit patterns). */
final case class RayRecord(number: Long, origin: Seq[Long], dir: Seq[Long], tmin: Long, tmax: Long, shadow: Boolean)

/** The answer for one ray, as the hardware's `hits` port gives it. */
final case class HitRecord(number: Long, hit: Boolean, t: Long, u: Long, v: Long, prim: Long, errors: Int)

/** A ray's constants as a datapath's golden model computes them. */
final case class PreparedGolden[S](statics: S, tmax: BigInt, dirNeg: Seq[Boolean], errors: Int)

/** The golden model of a datapath's arithmetic, bit for bit with its units. */
trait ArithGolden[S] {

  /** Format of the box tests' entry distances. */
  def boxFormat: FloatFormat

  /** Format of t, u, v and of the ray's tmax. */
  def triFormat: FloatFormat
  def prep(ray: RayRecord): PreparedGolden[S]

  /** One box (a nori node's, or one child slot's), `tmax` in the triangle format: (hit, entry distance in the box format). */
  def box(s: S, tmax: BigInt, node: NodeRecord): (Boolean, BigInt)

  /** BoxTest.Grid: a quantized node's K children tested in its grid (GridNode, GridLane, bit for bit
    * with GridBboxIntersect), `tmax` in the triangle format: per slot (hit, entry relative to the node).
    */
  def gridBox(
      s: S,
      tmax: BigInt,
      p: GridParams,
      grid: QuantNode.GridSoft,
      present: Seq[Boolean]
  ): Seq[(Boolean, BigInt)] =
    throw new IllegalArgumentException(
      "boxTest = grid needs a float datapath (FloatGolden): this one has no grid box test"
    )

  /** (t, u, v) in the triangle format, or None. Includes tmin <= t <= tmax. */
  def prim(s: S, tmax: BigInt, tri: TriangleRecord): Option[(BigInt, BigInt, BigInt)]
  def toFloat32(x: BigInt): Long
}

/** The whole accelerator's answer for one ray, visiting nodes in the
  * hardware's order (ControlGolden) and reducing each leaf as LeafIntersect
  * does (smallest t, ties to smaller prim, against the tmax at leaf entry).
  * The hardware must match it bit for bit, whatever its memory does.
  */
object TraversalGolden {
  final case class Trace(hit: HitRecord, boxTests: Int, triTests: Int, decisions: Int)

  /** `onNode` is told the index of every node the walk fetches, in order (the root first): the node reads the hardware makes.
    * `onLeaf` is told each leaf the walk enters (its first triangle slot and count), before `onTri` is told the slot of
    * each triangle it tests there (a shadow ray stops testing at its first occluder). */
  def trace[S](
      cfg: AccelConfig,
      img: MemoryImage,
      arith: ArithGolden[S],
      ray: RayRecord,
      onNode: Long => Unit = _ => (),
      onLeaf: (Long, Int) => Unit = (_, _) => (),
      onTri: Long => Unit = _ => ()
  ): Trace = {
    val fmt = arith.triFormat
    val p = arith.prep(ray)
    val stack = mutable.ArrayBuffer.empty[ControlGolden.Ref]
    var tok = ControlGolden.Token(0, 0, 0, p.dirNeg, ray.shadow, p.errors)
    var tmax = p.tmax
    var best: Option[(BigInt, BigInt, BigInt, Long)] = None
    var occluded = false
    var boxTests, triTests, decisions = 0
    var state: ControlGolden.State = ControlGolden.Traverse
    var (node, grid) = fetchNode(cfg, img, 0)
    onNode(0)
    var fromLeaf = false
    while (state != ControlGolden.Done) {
      // A ray back from a leaf only pops: no node, no box test.
      val (hits, view) =
        if (fromLeaf) (Nil, NoNode) else { boxTests += 1; testNode(cfg, arith, p.statics, tmax, node, grid) }
      val out = ControlGolden.step(cfg.layout, cfg.stackDepth, stack, tok, fromLeaf, occluded, hits, view)
      decisions += 1
      tok = out.token
      state = out.state
      fromLeaf = false
      state match {
        case ControlGolden.Traverse | ControlGolden.GoBack =>
          val (n, g) = fetchNode(cfg, img, tok.nodeIdx); node = n; grid = g; onNode(tok.nodeIdx)
        case ControlGolden.Leaf =>
          var leafErrors = 0
          val leafTmax = tmax
          var i = 0
          onLeaf(out.leafFirst, out.leafCount)
          // A shadow ray stops at its first occluder; which one the hardware
          // finds first depends on timing, so only `hit` is compared for them.
          while (i < out.leafCount && !(ray.shadow && occluded)) {
            val tri = Records.triangle(img, out.leafFirst + i)
            onTri(out.leafFirst + i)
            triTests += 1
            if (tri.vertexWords.exists(ErrorFlags.nonFiniteWord)) leafErrors |= 1 << ErrorFlags.BadSceneData
            if (tri.prim >= (1L << cfg.triIndexBits)) leafErrors |= 1 << ErrorFlags.IndexOverflow
            else arith.prim(p.statics, leafTmax, tri).foreach { case (t, u, v) =>
              val closer = best.forall { case (bt, _, _, bp) =>
                val (k, bk) = (FpOrder.keyOf(fmt, t), FpOrder.keyOf(fmt, bt))
                k < bk || (k == bk && tri.prim < bp)
              }
              if (closer) best = Some((t, u, v, tri.prim))
              if (ray.shadow) occluded = true
            }
            i += 1
          }
          best.foreach(b => tmax = b._1)
          tok = tok.copy(errors = tok.errors | leafErrors)
          fromLeaf = true
        case ControlGolden.Done => ()
      }
    }
    val ok = tok.errors == 0
    val hit = ok && best.isDefined
    val h = best.filter(_ => hit)
    Trace(
      HitRecord(
        ray.number,
        hit,
        h.fold(0L)(b => arith.toFloat32(b._1)),
        h.fold(0L)(b => arith.toFloat32(b._2)),
        h.fold(0L)(b => arith.toFloat32(b._3)),
        h.fold(0L)(_._4),
        tok.errors
      ),
      boxTests,
      triTests,
      decisions
    )
  }

  /** Does the hardware's answer for `ray` agree with the golden one? For a
    * shadow ray only occlusion and the error bits: which occluder it finds
    * first depends on memory timing, so its t/u/v/prim are not compared.
    */
  def agrees(ray: RayRecord, hw: HitRecord, golden: HitRecord): Boolean =
    if (ray.shadow) hw.hit == golden.hit && hw.errors == golden.errors else hw == golden

  private val NoNode = ControlGolden.NodeView(IndexedSeq.empty, 0, 0)

  /** Node `i`'s grid as GridBboxIntersect reads it, with grid box tests (else None). */
  def gridOf(cfg: AccelConfig, img: MemoryImage, i: Long): Option[QuantNode.GridSoft] =
    Option.when(cfg.gridBox)(QuantNode.decodeGridSoft(cfg.boxLanes, Records.nodeBytes(img, i)))

  /** Node `i` as the walk reads it: its slots and, with grid box tests, its
    * grid, from one read of its record. With grid box tests the slots carry
    * no FP32 boxes: GridBboxIntersect reads the raw grid and `nodeView` takes
    * the grid's `bad` in place of non-finite planes, so decoding them would
    * be work thrown away.
    */
  def fetchNode(cfg: AccelConfig, img: MemoryImage, i: Long): (IndexedSeq[NodeRecord], Option[QuantNode.GridSoft]) =
    if (!cfg.gridBox) (Records.node(img, i), None)
    else {
      val bytes = Records.nodeBytes(img, i)
      (Records.quantized(cfg.boxLanes, bytes, planes = false), Some(QuantNode.decodeGridSoft(cfg.boxLanes, bytes)))
    }

  /** BboxIntersect's answer for each slot of `node` (an empty slot never
    * hits), and the node as TraversalControl sees it; with grid box tests
    * (`grid`, the node's raw grid) GridBboxIntersect's, its integer entry
    * distances ordering the children.
    */
  def testNode[S](
      cfg: AccelConfig,
      arith: ArithGolden[S],
      statics: S,
      tmax: BigInt,
      node: IndexedSeq[NodeRecord],
      grid: Option[QuantNode.GridSoft] = None
  ): (Seq[ControlGolden.SlotHit], ControlGolden.NodeView) = {
    val d = nodeView(cfg, node, grid.map(_.bad))
    val hits = grid match {
      case Some(g) =>
        arith.gridBox(statics, tmax, cfg.gridParams, g, d.present).map { case (h, near) =>
          ControlGolden.SlotHit(h, near)
        }
      case None =>
        node.indices.map { i =>
          val (hit, near) = if (d.present(i)) arith.box(statics, tmax, node(i)) else (false, BigInt(0))
          ControlGolden.SlotHit(d.present(i) && hit, FpOrder.keyOf(arith.boxFormat, near))
        }
    }
    (hits, d.view)
  }

  /** A node's slots as the hardware decodes them for `cfg` (BvhNode.decode). */
  final case class Decoded(view: ControlGolden.NodeView, present: IndexedSeq[Boolean])

  /** `gridBad`: with grid box tests, the node's grid is bad (QuantNode.decodeGrid), which a used
    * slot flags in place of non-finite FP32 planes.
    */
  def nodeView(cfg: AccelConfig, slots: IndexedSeq[NodeRecord], gridBad: Option[Boolean] = None): Decoded = {
    require(slots.size == cfg.boxLanes, s"a ${cfg.layout.name} node has ${cfg.boxLanes} slots, got ${slots.size}")
    def fits(w: Long, bits: Int) = bits >= 32 || (w >> bits) == 0
    val decoded = slots.map { n =>
      val (present, badKind) = cfg.layout match {
        case BvhLayout.Nori => (true, !n.isLeaf && n.low31 > 2)
        case _: BvhLayout.Wide =>
          (n.word0 != BvhNode.EmptySlot, !n.isLeaf && n.word0 != 0 && n.word0 != BvhNode.EmptySlot)
      }
      val tooWide = badKind || !fits(n.word1, if (n.isLeaf) cfg.triIndexBits else cfg.nodeIndexBits)
      val leafBig = n.isLeaf && n.low31 > cfg.maxLeafSize
      val badBox = gridBad.getOrElse((n.boxMin ++ n.boxMax).exists(ErrorFlags.nonFiniteWord))
      val errors = if (!present) 0
      else
        (if (tooWide) 1 << ErrorFlags.IndexOverflow else 0) | (if (leafBig) 1 << ErrorFlags.LeafTooBig else 0) |
          (if (badBox) 1 << ErrorFlags.BadSceneData else 0)
      val mask = (1L << cfg.leafCountBits) - 1
      val index = if (n.isLeaf) n.word1 & ((1L << cfg.triIndexBits) - 1) else n.word1 & ((1L << cfg.nodeIndexBits) - 1)
      (ControlGolden.Ref(n.isLeaf, index, (n.word0 & mask).toInt), present, errors)
    }
    Decoded(
      ControlGolden.NodeView(decoded.map(_._1), (slots(0).word0 & 3).toInt, decoded.map(_._3).foldLeft(0)(_ | _)),
      decoded.map(_._2)
    )
  }
}
