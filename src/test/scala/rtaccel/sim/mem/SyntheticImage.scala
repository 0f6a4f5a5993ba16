package rtaccel.sim.mem

import rtaccel.scene.MemoryImage

import java.nio.{ByteBuffer, ByteOrder}
import scala.util.Random

/** A memory image with a valid header and random node/triangle bytes, for
  * tests of the memory model that need bytes, not a meaningful BVH.
  */
object SyntheticImage {

  /** Triangle requests of 48 bytes (TriangleRecord.RecordBytes) at a 48-byte stride, not the image's 64: every other
    * one then straddles two bursts, the case a memory model must charge and fetch right.
    */
  val Tri48: Int = rtaccel.leaf.TriangleRecord.RecordBytes
  def tri48(img: MemoryImage, i: Long): Long = img.triOffset + Tri48.toLong * i

  def apply(
      nodes: Int,
      tris: Int,
      rnd: Random,
      layout: rtaccel.bvh.BvhLayout = rtaccel.bvh.BvhLayout.Nori
  ): MemoryImage = {
    def align64(x: Int) = (x + 63) / 64 * 64
    val nodeOffset = MemoryImage.HeaderBytes
    val triOffset = align64(nodeOffset + nodes * layout.nodeBytes)
    val total = triOffset + tris * MemoryImage.TriBytes
    val bytes = new Array[Byte](total)
    rnd.nextBytes(bytes)
    val h = ByteBuffer.wrap(bytes, 0, MemoryImage.HeaderBytes).order(ByteOrder.LITTLE_ENDIAN)
    h.put(MemoryImage.Magic)
    Seq(
      MemoryImage.Version,
      nodes,
      tris,
      nodeOffset,
      triOffset,
      layout.nodeBytes,
      MemoryImage.TriBytes,
      4,
      8,
      layout.code
    )
      .foreach(v => h.putInt(v.toInt))
    while (h.position() < MemoryImage.HeaderBytes) h.put(0.toByte)
    MemoryImage.fromBytes("synthetic", bytes)
  }
}
