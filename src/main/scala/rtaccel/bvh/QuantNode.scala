package rtaccel.bvh

import chisel3._
import chisel3.util._
import rtaccel.fp.{FloatFormat, FpAdd, FpModel, RoundingMode}

/** A child slot as a 32-byte wide-slot record would hold it: word0, word1
  * and the FP32 box words. Quantized nodes are decoded into these, so one
  * set of checks (BvhNode.decode) serves every wide layout.
  */
final case class SlotWords[W](word0: W, word1: W, boxMin: Seq[W], boxMax: Seq[W])

/** The quantized wide node (layouts `4q`, `8q`; docs/memory-format.md,
  * "Quantized wide node"): bytes 0-11 origin (FP32 x, y, z), 12-14 scale
  * exponents e (scale 2^(e-127)), 15 zero, 16-19 childBase, 20-23 triBase,
  * then one meta byte per slot, then the 8-bit plane offsets q: lo x, lo y,
  * lo z, hi x, hi y, hi z, k bytes each (slot order); zero padding.
  *
  * A plane decodes to origin + q 2^(e-127) in one FP32 add. nori-bridge
  * writes origin = m 2^(e-127) with |m| <= 2^24 - 256, so the exact sum
  * (m + q) 2^(e-127) has an integer significand below 2^24 and is an FP32
  * number: the add rounds nothing, and the decoded box is the stored
  * (outward-quantized) box exactly (docs/kernels.md, "Quantized boxes").
  * A scale exponent outside ExpMin..ExpMax decodes to NaN planes, which
  * BvhNode.decode flags as bad scene data.
  */
object QuantNode {
  val FixedBytes = 24
  val ExpMin = 1
  val ExpMax = 247
  val MetaEmpty = 0x00
  val MetaInner = 0x01
  val MetaLeaf = 0x80

  /** The canonical quiet NaN a bad scale decodes to. */
  val NaN32: Long = 0x7fc00000L

  def nodeBytes(k: Int): Int = (FixedBytes + 7 * k + 15) / 16 * 16

  /** Byte offset of plane p (0..2 lo x, y, z; 3..5 hi x, y, z) of slot s. */
  def planeByte(k: Int, p: Int, s: Int): Int = FixedBytes + k + p * k + s

  // ---- Hardware ----

  /** Byte i and the little-endian 32-bit word at byte i of a record. */
  private def byteAt(record: UInt, i: Int): UInt = record(8 * i + 7, 8 * i)
  private def wordAt(record: UInt, i: Int): UInt = record(8 * i + 31, 8 * i)

  /** The k slots of a little-endian quantized node record. One FP32 adder
    * (combinational, exact for valid images) per plane per slot.
    */
  def decode(k: Int, record: UInt, before: Seq[(UInt, UInt)]): Seq[SlotWords[UInt]] = {
    require(record.getWidth == nodeBytes(k) * 8, s"QuantNode.decode: record must be ${nodeBytes(k) * 8} bits")
    val origin = (0 until 3).map(a => wordAt(record, 4 * a))
    val exp = (0 until 3).map(a => byteAt(record, 12 + a))
    val badExp = exp.map(e => e < ExpMin.U || e > ExpMax.U)
    for ((s, (w0, w1)) <- refs(k, record, before).zipWithIndex.map(_.swap)) yield {
      def plane(p: Int): UInt = {
        val a = p % 3
        val sum = Module(new FpAdd(FloatFormat.FP32, Some(RoundingMode.RNE), latency = 0))
        sum.io.in.valid := true.B
        sum.io.in.bits.a := origin(a)
        sum.io.in.bits.b := scaled(byteAt(record, planeByte(k, p, s)), exp(a))
        Mux(badExp(a), NaN32.U(32.W), sum.io.out.bits)
      }
      SlotWords(w0, w1, (0 until 3).map(plane), (3 until 6).map(plane))
    }
  }

  /** A quantized record as the grid box test reads it: slots whose box words
    * are the raw 8-bit plane offsets, the node's origin and exponent fields,
    * and `bad`: a scale exponent outside ExpMin..ExpMax or a non-finite origin.
    */
  final case class Grid(slots: Seq[SlotWords[UInt]], origin: Seq[UInt], exp: Seq[UInt], bad: Bool)

  def decodeGrid(k: Int, record: UInt, before: Seq[(UInt, UInt)]): Grid = {
    require(record.getWidth == nodeBytes(k) * 8, s"QuantNode.decodeGrid: record must be ${nodeBytes(k) * 8} bits")
    val origin = (0 until 3).map(a => record(32 * a + 31, 32 * a))
    val exp = (0 until 3).map(a => byteAt(record, 12 + a))
    val bad = (exp.map(e => e < ExpMin.U || e > ExpMax.U) ++ origin.map(_(30, 23).andR)).reduce(_ || _)
    val slots = for ((s, (w0, w1)) <- refs(k, record, before).zipWithIndex.map(_.swap))
      yield SlotWords(w0, w1, (0 until 3).map(p => byteAt(record, planeByte(k, p, s))), (3 until 6).map(p => byteAt(record, planeByte(k, p, s))))
    Grid(slots, origin, exp, bad)
  }

  /** Width of a slot's [[befores]] leaf count: at most 7 leaf counts of up to 127 triangles. */
  val BeforeBits = 11

  /** Width of a slot's [[befores]] inner count: at most 7 inner slots. */
  val InnerBits = 3

  /** Per slot, what its child index adds to the node's bases: the inner slots before it (read by an inner slot)
    * and the leaf counts before it (read by a leaf). Sums over the meta bytes before the slot: a fetch registers
    * them before the index adders ([[refs]]), so that these sums and the 32-bit adds are not one path
    * (BvhNode.staged). Both counts are kept, the slot's kind picking one in [[refs]] beside its adders, and each is
    * shallow, as it starts at the node answer: the inner slots are counted in logic ([[ones]]), and the leaf
    * counts are added by full adders in logic down to two operands, then in one carry chain ([[total]]). A chain
    * of adders, each entered from the one before, and the kind's select behind them take 5.59 ns by the delay
    * model of docs/fmax.md, over the 200 MHz clock; these take 4.10 ns.
    */
  def befores(k: Int, record: UInt): Seq[(UInt, UInt)] = {
    val meta = (0 until k).map(s => byteAt(record, FixedBytes + s))
    val inner = meta.map(_ === MetaInner.U)
    val count = meta.map(m => Mux(m(7), m(6, 0), 0.U))
    for (s <- 0 until k) yield (ones(inner.take(s), InnerBits), total(count.take(s), BeforeBits))
  }

  /** How many of `bits` are set, as `width` bits: full and half adders in logic, no carry chain (a few bits' count
    * is a LUT or two). Each column of equal weight is reduced to one bit, its carries going to the next column.
    */
  private def ones(bits: Seq[Bool], width: Int): UInt = {
    require(bits.size < (1 << width), s"QuantNode.ones: ${bits.size} bits do not fit a $width-bit count")
    var column = bits
    val out = for (_ <- 0 until width) yield {
      var carries = Seq.empty[Bool]
      while (column.size > 1) {
        val (x, rest) = column.splitAt(3)
        column = rest :+ x.reduce(_ ^ _)
        carries :+= (if (x.size == 3) x(0) & x(1) | x(0) & x(2) | x(1) & x(2) else x(0) & x(1))
      }
      val bit = column.headOption.getOrElse(false.B)
      column = carries
      bit
    }
    VecInit(out).asUInt
  }

  /** The sum of `xs`, as `width` bits (the sum must fit): full adders in logic (carry-save: the bitwise sum and the
    * majority, one place up) take three operands to two until two are left, which one carry chain adds.
    */
  private def total(xs: Seq[UInt], width: Int): UInt = {
    def fit(x: UInt): UInt = x.pad(width)(width - 1, 0)
    xs match {
      case Seq()     => 0.U(width.W)
      case Seq(a)    => fit(a)
      case Seq(a, b) => fit(a +& b)
      case a +: b +: c +: rest =>
        val n = Seq(a, b, c).map(_.getWidth).max
        val (x, y, z) = (a.pad(n), b.pad(n), c.pad(n))
        total(rest :+ (x ^ y ^ z) :+ Cat(x & y | x & z | y & z, 0.U(1.W)), width)
    }
  }

  /** Slot s's word0 and word1 (a 32-byte wide slot's) from its meta byte, the bases and its [[befores]] counts. */
  private def refs(k: Int, record: UInt, before: Seq[(UInt, UInt)]): Seq[(UInt, UInt)] = {
    require(before.length == k, s"QuantNode.refs: ${before.length} counts for $k slots")
    val (childBase, triBase) = (wordAt(record, 16), wordAt(record, 20))
    for ((s, (innerBefore, trisBefore)) <- (0 until k).zip(before)) yield {
      val m = byteAt(record, FixedBytes + s)
      val (isEmpty, isInner, isLeaf) = (m === MetaEmpty.U, m === MetaInner.U, m(7))
      val count = m(6, 0)
      val w0 = Mux(
        isEmpty,
        BvhNode.EmptySlot.U(32.W),
        Mux(isInner, 0.U(32.W), Mux(isLeaf, Cat(1.U(1.W), 0.U(24.W), count), m.pad(32)))
      )
      // Both sums, then the select: the meta byte's compares run beside the adders, not before them.
      val w1 = Mux(isInner, childBase +% innerBefore, Mux(isLeaf, triBase +% trisBefore, 0.U))
      (w0, w1)
    }
  }

  /** q 2^(e-127) as FP32 bits: exact and normal (or +0) for e in ExpMin..ExpMax. */
  private def scaled(q: UInt, e: UInt): UInt = {
    val p = Log2(q) // 0..7: the leading one
    val sig = ((q.pad(31) << 23) >> p)(22, 0)
    Mux(q === 0.U, 0.U(32.W), Cat(0.U(1.W), (e +% p)(7, 0), sig))
  }

  // ---- Software (golden), bit for bit with `decode` ----

  /** `planes = false`: the slots' words only, boxes empty (no FP32 decode). */
  def decodeSoft(k: Int, bytes: IndexedSeq[Int], planes: Boolean = true): Seq[SlotWords[Long]] = {
    def u32(i: Int): Long = (0 until 4).map(j => bytes(i + j).toLong << (8 * j)).sum
    val origin = (0 until 3).map(a => u32(4 * a))
    val exp = (0 until 3).map(a => bytes(12 + a))
    val (childBase, triBase) = (u32(16), u32(20))
    var innerBefore, trisBefore = 0L
    for (s <- 0 until k) yield {
      val m = bytes(FixedBytes + s)
      val (w0, w1) =
        if (m == MetaEmpty) (BvhNode.EmptySlot, 0L)
        else if (m == MetaInner) { innerBefore += 1; (0L, (childBase + innerBefore - 1) & 0xffffffffL) }
        else if ((m & MetaLeaf) != 0) {
          val c = (m & 0x7f).toLong; trisBefore += c
          (0x80000000L | c, (triBase + trisBefore - c) & 0xffffffffL)
        } else (m.toLong, 0L)
      def plane(p: Int): Long = {
        val e = exp(p % 3)
        if (e < ExpMin || e > ExpMax) NaN32
        else {
          val q = bytes(planeByte(k, p, s))
          val scaledBits = FpModel.f32RawBits(q.toFloat * java.lang.Float.intBitsToFloat(e << 23))
          FpModel.add(FloatFormat.FP32, RoundingMode.RNE, BigInt(origin(p % 3)), scaledBits).toLong
        }
      }
      if (planes) SlotWords(w0, w1, (0 until 3).map(plane), (3 until 6).map(plane)) else SlotWords(w0, w1, Nil, Nil)
    }
  }

  /** [[decodeGrid]]'s grid in software: origin words, exponent fields, per slot
    * the plane offsets (lo x, y, z; hi x, y, z), and `bad`.
    */
  final case class GridSoft(origin: Seq[Long], exp: Seq[Int], qMin: Seq[Seq[Int]], qMax: Seq[Seq[Int]], bad: Boolean)

  def decodeGridSoft(k: Int, bytes: IndexedSeq[Int]): GridSoft = {
    def u32(i: Int): Long = (0 until 4).map(j => bytes(i + j).toLong << (8 * j)).sum
    val origin = (0 until 3).map(a => u32(4 * a))
    val exp = (0 until 3).map(a => bytes(12 + a))
    val bad = exp.exists(e => e < ExpMin || e > ExpMax) || origin.exists(o => ((o >> 23) & 0xff) == 0xff)
    def q(p0: Int) = (0 until k).map(s => (p0 until p0 + 3).map(p => bytes(planeByte(k, p, s))))
    GridSoft(origin, exp, q(0), q(3), bad)
  }
}
