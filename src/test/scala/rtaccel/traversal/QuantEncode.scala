package rtaccel.traversal

import rtaccel.bvh.QuantNode

/** The quantizer of nori-bridge (`bvh/quant.rs`), for specs that need a
  * quantized node of given exact boxes: per axis the smallest scale 2^s with
  * origin m 2^s = floor(L / 2^s) 2^s, |m| <= 2^24 - 256 and the node's extent
  * within 255 steps; child planes rounded outward (min down, max up).
  */
object QuantEncode {
  final case class Box(min: Seq[Float], max: Seq[Float])

  /** Node bytes with every used slot a one-triangle leaf, or None when the
    * boxes cannot be quantized (non-finite, inverted, or too wide).
    */
  def leaves(k: Int, boxes: Seq[Option[Box]]): Option[Array[Byte]] = {
    require(boxes.size == k)
    val used = boxes.flatten
    val ok = used.nonEmpty && used.forall(b =>
      (0 until 3).forall(a =>
        b.min(a).isFinite && b.max(a).isFinite && b.min(a) <= b.max(a)
      )
    )
    if (!ok) return None
    val bytes = new Array[Byte](QuantNode.nodeBytes(k))
    for (a <- 0 until 3) {
      val (lo, hi) = (used.map(_.min(a)).min.toDouble, used.map(_.max(a)).max.toDouble)
      val (s, m) = scale(lo, hi).getOrElse(return None)
      val sc = Math.scalb(1.0, s)
      putInt(bytes, 4 * a, java.lang.Float.floatToRawIntBits((m * sc).toFloat))
      bytes(12 + a) = (s + 127).toByte
      for ((b, i) <- boxes.zipWithIndex; x <- b) {
        bytes(QuantNode.planeByte(k, a, i)) = (Math.floor(x.min(a) / sc) - m).toInt.toByte
        bytes(QuantNode.planeByte(k, 3 + a, i)) = (Math.ceil(x.max(a) / sc) - m).toInt.toByte
      }
    }
    for ((b, i) <- boxes.zipWithIndex)
      bytes(QuantNode.FixedBytes + i) = (if (b.isDefined) QuantNode.MetaLeaf | 1 else QuantNode.MetaEmpty).toByte
    Some(bytes)
  }

  private def scale(lo: Double, hi: Double): Option[(Int, Double)] = {
    val limit = (1 << 24) - 256.0
    var s = -126
    if (hi > lo) s = s.max(Math.getExponent((hi - lo) / 255) - 1)
    val mag = lo.abs.max(hi.abs)
    if (mag > 0) s = s.max(Math.getExponent(mag) - 25)
    while (s <= 104) {
      val sc = Math.scalb(1.0, s)
      val m = Math.floor(lo / sc)
      if (m.abs <= limit && Math.ceil(hi / sc) - m <= 255) return Some((s, m))
      s += 1
    }
    None
  }

  private def putInt(b: Array[Byte], at: Int, v: Int): Unit = for (j <- 0 until 4) b(at + j) = (v >>> (8 * j)).toByte
}
