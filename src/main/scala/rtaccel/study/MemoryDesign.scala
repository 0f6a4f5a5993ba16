package rtaccel.study

import rtaccel.scene.MemoryImage
import rtaccel.system.SystemConfig

/** How triangle records lie in DRAM and how LeafIntersect reads them. */
sealed trait TriRecords {

  /** Bytes of one record in the array. */
  def recordBytes: Int

  /** True: one read per leaf entered (all its records, one contiguous access); false: one read per triangle tested. */
  def perLeaf: Boolean
  def name: String
}
object TriRecords {

  /** 48-byte records (nine FP32 vertex words, prim, flags, pad) on 16-byte boundaries, one read per test,
    * charged the one or two 64-byte lines it touches (1.5 on average). */
  case object Record48 extends TriRecords { val recordBytes = 48; val perLeaf = false; val name = "48 B, per triangle" }

  /** The image's records (docs/memory-format.md): padded to 64 bytes, every triangle one line. */
  case object Record64 extends TriRecords { val recordBytes = 64; val perLeaf = false; val name = "64 B, per triangle" }

  /** 48-byte records, a leaf's run of them read as one access. */
  case object Leaf48 extends TriRecords { val recordBytes = 48; val perLeaf = true; val name = "48 B, per leaf" }

  /** Nine FP32 vertex words only (the hit's prim from a host-side table of slot to prim), a leaf read as one
    * access. The vertex words are the same, so every answer is bit for bit today's. */
  case object Leaf36 extends TriRecords { val recordBytes = 36; val perLeaf = true; val name = "36 B, per leaf" }
}

/** One design point of the memory side, for the study: the stores (preloaded prefixes of the node and triangle
  * arrays, as `NodeStore` and `TriStore` hold them), the triangle records and the bytes a hit costs.
  * The node layout is the image's.
  */
final case class MemoryDesign(
    nodeStoreBytes: Long = SystemConfig().nodeStoreBytes.toLong,
    triStoreBytes: Long = SystemConfig().triStoreBytes.toLong,
    tris: TriRecords = TriRecords.Record64,
    /** DRAM bytes written per hit: 64 today (each 32-byte record is its own masked 64-byte burst); 32 when two
      * neighbouring records are written as one line. */
    hitBytes: Int = 64
) {
  import MemoryDesign._

  /** DRAM bytes of `read` in image `img`, 0 when a store serves it (whole 64-byte lines touched). */
  def bytes(img: MemoryImage, read: SceneRead): Long = read match {
    case NodeRead(i) =>
      if ((i + 1) * img.nodeBytes <= nodeStoreBytes) 0 else lineBytes(img.nodeAddr(i), img.nodeBytes)
    case TriRead(j) if !tris.perLeaf =>
      if ((j + 1) * tris.recordBytes <= triStoreBytes) 0
      else lineBytes(img.triOffset + j * tris.recordBytes, tris.recordBytes)
    case LeafRead(f, n) if tris.perLeaf =>
      if ((f + n) * tris.recordBytes <= triStoreBytes) 0
      else lineBytes(img.triOffset + f * tris.recordBytes, n.toLong * tris.recordBytes)
    case _ => 0
  }

  /** The 64-byte lines `read` touches in DRAM (none when a store serves it). */
  def lines(img: MemoryImage, read: SceneRead): Seq[Long] = {
    val span: Option[(Long, Long)] = read match {
      case NodeRead(i) if (i + 1) * img.nodeBytes > nodeStoreBytes => Some((img.nodeAddr(i), img.nodeBytes))
      case TriRead(j) if !tris.perLeaf && (j + 1) * tris.recordBytes > triStoreBytes =>
        Some((img.triOffset + j * tris.recordBytes, tris.recordBytes.toLong))
      case LeafRead(f, n) if tris.perLeaf && (f + n) * tris.recordBytes > triStoreBytes =>
        Some((img.triOffset + f * tris.recordBytes, n.toLong * tris.recordBytes))
      case _ => None
    }
    span.toSeq.flatMap { case (a, n) => (a / Line) to ((a + n - 1) / Line) }
  }

  def isNode(read: SceneRead): Boolean = read.isInstanceOf[NodeRead]

  /** BRAM36 of the two stores for `cores` cores: one dual-ported copy, its ports shared by the cores (NodeStore,
    * TriStore, `SystemConfig.storeCopies`), at the
    * measured 228 BRAM36 per MiB of either (docs/node-store.md, docs/scene-store.md: Yosys 0.23 synth_xilinx). */
  def storeBram(cores: Int): Int = copies(cores) * (bram(nodeStoreBytes) + bram(triStoreBytes))
}

object MemoryDesign {

  /** The DDR model's burst: every access is charged the whole 64-byte lines it touches. */
  val Line = 64L
  def lineBytes(addr: Long, n: Long): Long = Line * ((addr + n - 1) / Line - addr / Line + 1)

  /** Measured: 57 BRAM36 per 256 KiB of store (both stores, 512- and 1024-bit words). */
  def bram(bytes: Long): Int = math.ceil(bytes * 228.0 / (1 << 20)).toInt

  /** Store copies the system builds for `cores` cores: one (`SystemConfig.storeCopies`); beyond two cores the
    * cores share its two ports. */
  def copies(cores: Int): Int = rtaccel.system.SystemConfig().storeCopiesFor(cores)

  /** xc7z045 block RAM. */
  val DeviceBram36 = 545
}
