package rtaccel.scene

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.{Files, Path}

/** A nori-bridge memory image (`image.bin`), as specified in
  * docs/memory-format.md (version 3): a 64-byte little-endian header, then
  * BVH nodes of the header's layout (32-byte nori nodes, wide nodes of K
  * 32-byte child slots, or quantized wide nodes of 64 / 80 bytes) and 64-byte
  * triangle records (44 bytes of fields, zero padding), each section 64-byte
  * aligned.
  *
  * The hardware sees this file as its memory, byte address 0 = file offset 0.
  */
final class MemoryImage private (val source: String, val bytes: Array[Byte]) {
  import MemoryImage._
  private val header = ByteBuffer.wrap(bytes, 0, HeaderBytes).order(ByteOrder.LITTLE_ENDIAN)
  private def u32(offset: Int): Long = header.getInt(offset).toLong & 0xffffffffL

  val version: Long = u32(8)
  val nodeCount: Long = u32(12)
  val triCount: Long = u32(16)
  val nodeOffset: Long = u32(20)
  val triOffset: Long = u32(24)
  val nodeBytes: Long = u32(28)
  val triBytes: Long = u32(32)
  val maxLeafSize: Long = u32(36)

  /** The largest stack the layout's traversal can need. */
  val bvhDepth: Long = u32(40)
  val layout: rtaccel.bvh.BvhLayout = rtaccel.bvh.BvhLayout.fromCode(u32(44), source)

  private def fail(what: String): Nothing = throw new IllegalArgumentException(s"$source: $what")
  if (version != Version)
    fail(s"format version $version, this build reads version $Version: compile the package again with this nori-bridge")
  if (nodeBytes != layout.nodeBytes)
    fail(s"nodeBytes = $nodeBytes, expected ${layout.nodeBytes} for layout ${layout.name}")
  if (triBytes != TriBytes) fail(s"triBytes = $triBytes, expected $TriBytes")
  if (nodeCount < 1) fail("nodeCount = 0: an image needs at least a root node")
  if (nodeOffset % 64 != 0 || triOffset % 64 != 0)
    fail(s"sections not 64-byte aligned (nodeOffset=$nodeOffset, triOffset=$triOffset)")
  if (nodeOffset + nodeCount * nodeBytes > bytes.length)
    fail(s"node section [$nodeOffset, +${nodeCount * nodeBytes}) runs past the file end (${bytes.length} bytes)")
  if (triOffset + triCount * TriBytes > bytes.length)
    fail(s"triangle section [$triOffset, +${triCount * TriBytes}) runs past the file end (${bytes.length} bytes)")

  def nodeAddr(index: Long): Long = nodeOffset + index * nodeBytes
  def triAddr(index: Long): Long = triOffset + index * TriBytes

  private def check(addr: Long, n: Int): Unit =
    if (addr < 0 || addr + n > bytes.length)
      throw new IndexOutOfBoundsException(
        s"$source: read of $n bytes at address $addr is outside the image (${bytes.length} bytes)"
      )

  /** `n` bytes at `addr`, each 0..255. */
  def bytesAt(addr: Long, n: Int): IndexedSeq[Int] = {
    check(addr, n)
    IndexedSeq.tabulate(n)(i => bytes(addr.toInt + i) & 0xff)
  }

  /** `n` bytes at `addr` as an unsigned little-endian integer (byte 0 in bits 7..0). */
  def readLE(addr: Long, n: Int): BigInt = {
    check(addr, n)
    var v = BigInt(0)
    var i = n - 1
    while (i >= 0) { v = (v << 8) | (bytes(addr.toInt + i) & 0xff); i -= 1 }
    v
  }
}

object MemoryImage {
  val Magic: Array[Byte] = "RTACCEL\u0000".getBytes("US-ASCII")
  val Version = 3L
  val HeaderBytes = 64

  /** Bytes of a nori node, and of one wide-node slot. */
  val NodeBytes = 32

  /** A triangle record's stride: its 44 bytes of fields padded to one 64-byte
    * DRAM burst, so that no record straddles two bursts (a 48-byte stride
    * straddles on every other record and reads 96 bytes per triangle on
    * average, docs/dram-traffic.md).
    */
  val TriBytes = 64
  require(
    Integer.bitCount(TriBytes) == 1,
    s"MemoryImage: triBytes $TriBytes must be a power of two (a shift in hardware)"
  )

  def load(path: Path): MemoryImage = {
    if (!Files.exists(path))
      throw new IllegalArgumentException(
        s"$path: no such memory image (make one with `nori-bridge compile <scene.xml> --out <dir>`)"
      )
    fromBytes(path.toString, Files.readAllBytes(path))
  }

  def fromBytes(source: String, bytes: Array[Byte]): MemoryImage = {
    if (bytes.length < HeaderBytes)
      throw new IllegalArgumentException(s"$source: ${bytes.length} bytes is shorter than the $HeaderBytes-byte header")
    if (!bytes.take(8).sameElements(Magic))
      throw new IllegalArgumentException(
        s"$source: bad magic ${bytes.take(8).map(b => f"${b & 0xff}%02x").mkString} (expected 'RTACCEL\\0')"
      )
    new MemoryImage(source, bytes)
  }
}

/** A 32-byte node record's raw fields: a nori node, or one slot of a wide
  * node (docs/memory-format.md).
  */
final case class NodeRecord(word0: Long, word1: Long, boxMin: Seq[Long], boxMax: Seq[Long]) {
  def isLeaf: Boolean = (word0 >> 31) != 0
  def low31: Long = word0 & 0x7fffffffL
}

/** A triangle record's raw fields: nine FP32 vertex words, prim, flags. */
final case class TriangleRecord(vertexWords: Seq[Long], prim: Long, flags: Long)

object Records {

  /** Node `i`'s 32-byte records: the node itself (nori), or its K slots (wide;
    * a quantized node decoded as the hardware decodes it, rtaccel.bvh.QuantNode).
    */
  def node(img: MemoryImage, i: Long): IndexedSeq[NodeRecord] = img.layout match {
    case w: rtaccel.bvh.BvhLayout.Wide if w.quantized => quantized(w.k, nodeBytes(img, i), planes = true)
    case _ => (0 until img.layout.lanes).map { s =>
        val w = (0 until 8).map(k => img.readLE(img.nodeAddr(i) + 32 * s + 4 * k, 4).toLong)
        NodeRecord(w(0), w(1), w.slice(2, 5), w.slice(5, 8))
      }
  }

  /** Node `i`'s raw record. */
  def nodeBytes(img: MemoryImage, i: Long): IndexedSeq[Int] = img.bytesAt(img.nodeAddr(i), img.layout.nodeBytes)

  /** A quantized node's K slots from its record; `planes = false` leaves the
    * FP32 boxes empty (a grid box test reads the raw grid, not the planes).
    */
  def quantized(k: Int, bytes: IndexedSeq[Int], planes: Boolean): IndexedSeq[NodeRecord] =
    rtaccel.bvh.QuantNode.decodeSoft(k, bytes, planes).map(s => NodeRecord(s.word0, s.word1, s.boxMin, s.boxMax))
      .toIndexedSeq

  def triangle(img: MemoryImage, i: Long): TriangleRecord = {
    val w = (0 until 11).map(k => img.readLE(img.triAddr(i) + 4 * k, 4).toLong)
    TriangleRecord(w.take(9), w(9), w(10))
  }
}
