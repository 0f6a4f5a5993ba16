package rtaccel.sim.axi

import scala.collection.mutable

/** A byte-addressed memory of any size, kept as 4 KB pages allocated on
  * first write; unwritten bytes read as zero.
  */
final class SparseMemory {
  private val pages = mutable.HashMap.empty[Long, Array[Byte]]
  private def page(addr: Long): Array[Byte] = pages.getOrElseUpdate(addr >>> 12, new Array[Byte](4096))

  def write(addr: Long, bytes: Array[Byte]): Unit = {
    require(addr >= 0, s"SparseMemory: negative address $addr")
    var i = 0
    while (i < bytes.length) { page(addr + i)(((addr + i) & 4095).toInt) = bytes(i); i += 1 }
  }
  def read(addr: Long, n: Int): Array[Byte] = {
    require(addr >= 0 && n >= 0, s"SparseMemory: bad read of $n bytes at $addr")
    Array.tabulate(n)(i => pages.get((addr + i) >>> 12).fold(0.toByte)(_(((addr + i) & 4095).toInt)))
  }

  /** `n` bytes at `addr` as an unsigned little-endian integer (byte 0 in bits 7..0). */
  def readLE(addr: Long, n: Int): BigInt = SparseMemory.toLE(read(addr, n))
  def writeLE(addr: Long, n: Int, value: BigInt): Unit = write(addr, SparseMemory.fromLE(value, n))
}

object SparseMemory {
  def toLE(bytes: Array[Byte]): BigInt = bytes.reverseIterator.foldLeft(BigInt(0))((v, b) => (v << 8) | (b & 0xff))
  def fromLE(value: BigInt, n: Int): Array[Byte] = Array.tabulate(n)(i => ((value >> (8 * i)) & 0xff).toByte)
}
