package rtaccel.sim

import rtaccel.golden.{HitRecord, RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage
import rtaccel.{AccelConfig, ErrorFlags}
import rtaccel.bvh.BvhLayout

import scala.util.Random

/** The control-path workload shared by RtAccelControlSpec and `make soak`:
  * synthetic trees of each layout, random rays (some invalid, some shadow),
  * and the check of every answer against the golden traversal.
  */
object ControlWorkload {
  def f(x: Float): Long = java.lang.Float.floatToRawIntBits(x).toLong & 0xffffffffL

  def makeRays(rnd: Random, n: Int): IndexedSeq[RayRecord] = (0 until n).map { i =>
    val bad = rnd.nextInt(50) == 0 // NaN or inf: must come back with InvalidRay
    val o = Seq.fill(3)(rnd.nextInt().toLong & 0xffffffffL).map(w => w & 0x7f7fffffL | (w & 0x80000000L))
    val d = Seq.fill(3)(rnd.nextInt().toLong & 0xff7fffffL)
    RayRecord(
      i.toLong * 3 + 7,
      if (bad) o.updated(1, f(Float.NaN)) else o,
      if (bad && rnd.nextBoolean()) d.updated(2, f(Float.PositiveInfinity)) else d,
      f(0f),
      f((1 + rnd.nextInt(9)).toFloat),
      rnd.nextInt(4) == 0
    )
  }

  def check(
      cfg: AccelConfig,
      img: MemoryImage,
      rays: IndexedSeq[RayRecord],
      got: Seq[HitRecord],
      what: String
  ): Unit = {
    assert(got.size == rays.size, s"$what: ${got.size} hits for ${rays.size} rays")
    assert(got.map(_.number).toSet == rays.map(_.number).toSet, s"$what: the set of ray numbers differs")
    val byNumber = got.map(h => h.number -> h).toMap
    for (r <- rays) {
      val e = TraversalGolden.trace(cfg, img, FieldDatapath.Golden, r).hit
      val h = byNumber(r.number)
      val same = TraversalGolden.agrees(r, h, e)
      assert(
        same,
        s"$what: ray ${r.number} (shadow=${r.shadow}): hardware $h, golden $e (errors ${ErrorFlags.describe(h.errors)})"
      )
    }
  }

  /** The core configuration the control workload runs on (RtAccelControlSpec and `make soak`): `ids` ray IDs and a
    * stack as deep as [[treeOf]]'s trees need, so that only the trees built deeper than it overflow.
    */
  def config(layout: BvhLayout, ids: Int): AccelConfig = AccelConfig(
    numRayIds = ids,
    stackDepth = treeOf(layout, new Random(0))._2,
    maxNodes = 4096,
    maxTriangles = 4096,
    maxLeafSize = 4,
    layout = layout
  )

  /** A synthetic tree of `layout`, and a stack that overflows on its deepest paths only. */
  def treeOf(layout: BvhLayout, rnd: Random, leafChance: Double = 0.3): (MemoryImage, Int) = layout match {
    case BvhLayout.Nori => (SyntheticBvh(rnd, maxDepth = 7, maxLeaf = 4, leafChance), 5)
    case w: BvhLayout.Wide =>
      val depth = Map(2 -> 6, 4 -> 4, 8 -> 3)(w.k)
      (SyntheticBvh(rnd, maxDepth = depth, maxLeaf = 4, leafChance, layout), (depth - 1) * w.maxPushes)
  }

}
