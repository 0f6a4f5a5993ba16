package rtaccel.datapath

import chiseltest._
import rtaccel.datapath.GoldenRun.{BoxExp, PrimExp}
import rtaccel.datapath.KernelVectors.hex

/** Streams box and triangle cases through a [[DatapathHarness]], one of each
  * per cycle, single-threaded (poke, peek, step) with a scoreboard queue, and
  * compares every output bit with its expected value. Returns the first
  * mismatches (empty = all equal).
  */
object DatapathDriver {
  final case class Work(boxes: IndexedSeq[(KernelCase, BoxExp)], prims: IndexedSeq[(KernelCase, PrimExp)])

  private def pack(xs: Seq[BigInt]): BigInt = xs.zipWithIndex.map { case (x, i) => x << (32 * i) }.sum

  def run(dut: DatapathHarness, work: Work, maxReport: Int = 10): Seq[String] = {
    val (bw, w) = (dut.dp.boxFmt.width, dut.dp.triFmt.width)
    val (bmask, mask) = ((BigInt(1) << bw) - 1, (BigInt(1) << w) - 1)
    val n = work.boxes.size max work.prims.size
    val bad = scala.collection.mutable.ArrayBuffer.empty[String]
    val inFlight = scala.collection.mutable.Queue.empty[Int]
    def check(i: Int): Unit = {
      assert(dut.io.outValid.peek().litToBoolean, s"no valid output for case $i at latency ${dut.latency}")
      if (i < work.boxes.size) {
        val (c, e) = work.boxes(i)
        val o = dut.io.boxOut.peek().litValue
        val got = BoxExp(o.testBit(bw + 1), o.testBit(bw), o & bmask)
        if (got != e && bad.size < maxReport)
          bad += s"box ${c.where}: hw (err ${got.err}, hit ${got.hit}, near ${hex(got.near)}) " +
            s"want (err ${e.err}, hit ${e.hit}, near ${hex(e.near)})"
      }
      if (i < work.prims.size) {
        val (c, e) = work.prims(i)
        val o = dut.io.primOut.peek().litValue
        val got = PrimExp(o.testBit(3 * w + 1), o.testBit(3 * w), (o >> (2 * w)) & mask, (o >> w) & mask, o & mask)
        if (got != e && bad.size < maxReport) bad += s"prim ${c.where}: hw $got want $e"
      }
    }
    dut.clock.setTimeout(0)
    for (cycle <- 0 until n + dut.latency) {
      if (cycle < n) {
        val b = work.boxes(cycle min (work.boxes.size - 1))._1
        val p = work.prims(cycle min (work.prims.size - 1))._1
        dut.io.valid.poke(true)
        dut.io.boxRay.poke(pack(b.in.slice(0, 8)))
        dut.io.box.poke(pack(b.in.slice(8, 14)))
        dut.io.triRay.poke(pack(p.in.slice(0, 8)))
        dut.io.tri.poke(pack(p.in.slice(8, 17)))
        inFlight.enqueue(cycle)
      } else dut.io.valid.poke(false)
      if (cycle >= dut.latency) check(inFlight.dequeue())
      dut.clock.step()
    }
    assert(inFlight.isEmpty && !dut.io.outValid.peek().litToBoolean, "output valid after the last case")
    bad.toSeq
  }
}
