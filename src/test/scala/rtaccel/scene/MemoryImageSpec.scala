package rtaccel.scene

import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.sim.mem.SyntheticImage

import java.nio.{ByteBuffer, ByteOrder}
import java.nio.file.{Files, Paths}
import scala.util.Random

/** The memory image's reader (docs/memory-format.md): triangle records one 64-byte line apart, and an image of
  * another format version or record size refused with its file and value named.
  */
class MemoryImageSpec extends AnyFlatSpec {
  behavior of "MemoryImage"

  it should "place triangle j at triOffset + 64 j, one whole 64-byte line" in {
    val img = SyntheticImage(nodes = 3, tris = 5, new Random(1))
    assert(MemoryImage.TriBytes == 64 && img.triOffset % 64 == 0)
    assert((0 until 5).map(j => img.triAddr(j.toLong)) == (0 until 5).map(j => img.triOffset + 64L * j))
    assert(img.bytes.length == img.triOffset + 64 * 5)
  }

  it should "refuse another format version or triangle size, naming the source and the value" in {
    val img = SyntheticImage(nodes = 3, tris = 5, new Random(2))
    def patched(word: Int, value: Int): Array[Byte] = {
      val b = img.bytes.clone()
      ByteBuffer.wrap(b).order(ByteOrder.LITTLE_ENDIAN).putInt(4 * word, value)
      b
    }
    val old = intercept[IllegalArgumentException](MemoryImage.fromBytes("old.bin", patched(2, 2)))
    assert(old.getMessage.contains("old.bin") && old.getMessage.contains("format version 2"), old.getMessage)
    val tri48 = intercept[IllegalArgumentException](MemoryImage.fromBytes("t48.bin", patched(8, 48)))
    assert(tri48.getMessage.contains("t48.bin") && tri48.getMessage.contains("triBytes = 48"), tri48.getMessage)
  }

  it should "share its format version with the Makefile's package stamp, so a new format compiles packages again" in {
    val stamp = "(?m)^IMAGE_FORMAT := (\\d+)$".r.findFirstMatchIn(Files.readString(Paths.get("Makefile")))
    assert(stamp.map(_.group(1).toLong).contains(MemoryImage.Version), s"Makefile IMAGE_FORMAT: $stamp")
  }
}
