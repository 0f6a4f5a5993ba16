package rtaccel.bvh

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, ErrorFlags}

/** Where a child of a node leads: an inner node to fetch, or a leaf's
  * triangle range. It is also what a ray's stack holds.
  */
class ChildRef(cfg: AccelConfig) extends Bundle {
  val isLeaf = Bool()

  /** Node index (inner child) or first triangle slot (leaf). */
  val index = UInt(cfg.refIndexBits.W)

  /** Triangles in the leaf (leaf only). */
  val count = UInt(cfg.leafCountBits.W)
}

/** One child slot of a decoded node: its box and where it leads. The box is
  * raw FP32 bits (BboxIntersect narrows them to its format), or with grid box
  * tests the slot's 8-bit plane offsets in its node's grid (QuantNode), which
  * is all GridBboxIntersect reads: no FP32 plane is ever formed.
  */
class NodeSlot(cfg: AccelConfig) extends Bundle {
  val present = Bool()
  val child = new ChildRef(cfg)
  val boxMin = Option.when(!cfg.gridBox)(Vec(3, UInt(32.W)))
  val boxMax = Option.when(!cfg.gridBox)(Vec(3, UInt(32.W)))

  /** Grid box tests: plane offsets lo x, y, z and hi x, y, z. */
  val qMin = Option.when(cfg.gridBox)(Vec(3, UInt(cfg.gridParams.qBits.W)))
  val qMax = Option.when(cfg.gridBox)(Vec(3, UInt(cfg.gridParams.qBits.W)))
}

/** A quantized node's grid as the record holds it (grid box tests only):
  * per axis the origin (FP32) and scale exponent field e (scale 2^(e-127)).
  */
class NodeGrid extends Bundle {
  val origin = Vec(3, UInt(32.W))
  val exp = Vec(3, UInt(8.W))
}

/** A decoded node record (docs/memory-format.md, version 2).
  *
  *  - Nori layout: one slot, the node itself (its own box; a leaf's range, or
  *    for an inner node `ref.index` = its right child, the left being the next
  *    node), and the split axis that picks the near child.
  *  - Wide layout: `cfg.boxLanes` slots, one per child, used slots first.
  */
class BvhNode(cfg: AccelConfig) extends Bundle {
  val slots = Vec(cfg.boxLanes, new NodeSlot(cfg))

  /** Nori layout only: split axis of an inner node. */
  val axis = UInt(2.W)

  /** The record does not fit this hardware, or is corrupt: see ErrorFlags. */
  val errors = ErrorFlags()

  /** Grid box tests: the node's grid (the slots hold offsets in it). */
  val grid = Option.when(cfg.gridBox)(new NodeGrid)
}

/** A node record as a staged fetch registers it first (BvhNode.record): the record and, in the quantized layouts,
  * its slots' QuantNode.befores counts, the inner slots and the leaf counts before each (none otherwise).
  */
class NodeRecord(cfg: AccelConfig) extends Bundle {
  private val n = if (cfg.layout.quantized) cfg.boxLanes else 0
  val data = UInt((cfg.layout.nodeBytes * 8).W)
  val innerBefore = Vec(n, UInt(QuantNode.InnerBits.W))
  val trisBefore = Vec(n, UInt(QuantNode.BeforeBits.W))

  /** Per slot, the inner slots and the leaf counts before it, as QuantNode reads them. */
  def before: Seq[(UInt, UInt)] = innerBefore.zip(trisBefore)
}

/** A node record's slots as 32-byte wide-slot words (BvhNode.words): word0 (kind or leaf count), word1 (child
  * index) and the planes, FP32 bits or with grid box tests the 8-bit offsets; with grid box tests the grid and
  * its `bad` flag. What a staged fetch registers before the checks (BvhNode.staged).
  */
class NodeWords(cfg: AccelConfig) extends Bundle {
  private val planeBits = if (cfg.gridBox) cfg.gridParams.qBits else 32
  val slots = Vec(
    cfg.boxLanes,
    new Bundle {
      val word0 = UInt(32.W)
      val word1 = UInt(32.W)
      val lo = Vec(3, UInt(planeBits.W))
      val hi = Vec(3, UInt(planeBits.W))
    }
  )
  val grid = Option.when(cfg.gridBox)(new NodeGrid)
  val gridBad = Option.when(cfg.gridBox)(Bool())
}

object BvhNode {

  /** Slot `word0` of an empty wide-node slot. */
  val EmptySlot: Long = 0x40000000L

  /** Decodes a little-endian node record of `cfg.layout`, flagging fields too
    * wide for `cfg`, corrupt kind words and non-finite bounds. Only used slots
    * can flag. A quantized node's boxes are decoded to FP32 here (QuantNode),
    * so the box lanes see exact FP32 boxes in every layout; with grid box
    * tests they stay raw (QuantNode.decodeGrid), and a used slot flags bad
    * scene data where the FP32 decode would have a non-finite plane for a
    * reason visible in the record: a scale exponent outside ExpMin..ExpMax or
    * a non-finite origin (an origin so large that a plane overflows, which
    * nori-bridge never writes, is not flagged: the grid test still bounds it).
    */
  def decode(cfg: AccelConfig, record: UInt): BvhNode = check(cfg, words(cfg, record))

  /** Whether a fetch decodes a record in two registered stages before [[check]]: in the quantized layouts a slot's
    * child index is the node's base plus the counts of the slots before it (QuantNode.befores, a prefix sum), and
    * that sum, the 32-bit add and the checks behind it were a node fetch's longest path (19 cells, 10.3 ns by the
    * delay model of docs/fmax.md). So a fetch registers the record with its slots' counts ([[record]]), then the
    * words ([[words]]), then the node. Plain layouts copy the words from the record and need neither stage.
    */
  def staged(cfg: AccelConfig): Boolean = cfg.layout.quantized

  /** A record with its slots' [[QuantNode.befores]] counts: the first register of a staged fetch. */
  def record(cfg: AccelConfig, data: UInt): NodeRecord = {
    val r = Wire(new NodeRecord(cfg))
    r.data := data
    if (cfg.layout.quantized) {
      val before = QuantNode.befores(cfg.boxLanes, data)
      r.innerBefore := VecInit(before.map(_._1))
      r.trisBefore := VecInit(before.map(_._2))
    }
    r
  }

  /** A node record's slots as words: what a 32-byte wide slot would hold (QuantNode decodes a quantized record
    * into the same), with the grid's fields for grid box tests. [[check]] turns them into the node.
    */
  def words(cfg: AccelConfig, data: UInt): NodeWords = words(cfg, record(cfg, data))

  def words(cfg: AccelConfig, r: NodeRecord): NodeWords = {
    val bytes = cfg.layout.nodeBytes
    val record = r.data
    require(record.getWidth == bytes * 8, s"BvhNode.words: record must be ${bytes * 8} bits")
    def word(slot: Int, i: Int): UInt = record(256 * slot + 32 * i + 31, 256 * slot + 32 * i)
    // A quantized node is first decoded into the slot words a 32-byte slot would hold.
    val gridRaw = Option.when(cfg.gridBox)(QuantNode.decodeGrid(cfg.boxLanes, record, r.before))
    val raw: Seq[SlotWords[UInt]] = cfg.layout match {
      case _ if cfg.gridBox                 => gridRaw.get.slots
      case w: BvhLayout.Wide if w.quantized => QuantNode.decode(w.k, record, r.before)
      case _ => (0 until cfg.boxLanes).map(s =>
          SlotWords(word(s, 0), word(s, 1), (2 until 5).map(word(s, _)), (5 until 8).map(word(s, _)))
        )
    }
    val w = Wire(new NodeWords(cfg))
    for ((x, r) <- w.slots.zip(raw)) {
      x.word0 := r.word0
      x.word1 := r.word1
      x.lo := VecInit(r.boxMin)
      x.hi := VecInit(r.boxMax)
    }
    for (g <- w.grid; r <- gridRaw) {
      g.origin := VecInit(r.origin)
      g.exp := VecInit(r.exp)
    }
    for (b <- w.gridBad; r <- gridRaw) b := r.bad
    w
  }

  /** The node from its words, flagging fields too wide for `cfg`, corrupt kind words and bad boxes. */
  def check(cfg: AccelConfig, w: NodeWords): BvhNode = {
    val n = fields(cfg, w)
    n.errors := errors(slotChecks(cfg, w))
    n
  }

  /** The node from its words, its error flags left unset (DontCare): [[check]] without [[slotChecks]]. */
  def fields(cfg: AccelConfig, w: NodeWords): BvhNode = {
    val n = Wire(new BvhNode(cfg))
    n.errors := DontCare
    for ((slot, x) <- n.slots.zip(w.slots)) {
      val leaf = x.word0(31)
      slot.child.isLeaf := leaf
      slot.child.index := x.word1(cfg.refIndexBits - 1, 0)
      slot.child.count := x.word0(cfg.leafCountBits - 1, 0)
      for (a <- 0 until 3) {
        slot.boxMin.foreach(_(a) := x.lo(a))
        slot.boxMax.foreach(_(a) := x.hi(a))
        slot.qMin.foreach(_(a) := x.lo(a))
        slot.qMax.foreach(_(a) := x.hi(a))
      }
      slot.present := present(cfg, x.word0)
    }
    for (g <- n.grid; r <- w.grid) g := r
    n.axis := w.slots(0).word0(1, 0)
    n
  }

  /** A slot is used: the nori layout's one slot always; a wide slot unless its word0 is EmptySlot. */
  private def present(cfg: AccelConfig, word0: UInt): Bool = cfg.layout match {
    case BvhLayout.Nori    => true.B
    case _: BvhLayout.Wide => word0 =/= EmptySlot.U
  }

  /** What [[errors]] reads of one slot: each test on the record's words, before they are combined. A fetch may
    * register these (PrepFetch), so that the compares of whole words and the OR over the slots are not one path.
    */
  class SlotChecks extends Bundle {
    val present = Bool()
    val indexBad = Bool()
    val leafTooBig = Bool()
    val badBox = Bool()
  }

  def slotChecks(cfg: AccelConfig, w: NodeWords): Vec[SlotChecks] = {
    def highBitsSet(x: UInt, keep: Int): Bool = if (keep >= 32) false.B else x(31, keep).orR
    VecInit(w.slots.map { x =>
      val c = Wire(new SlotChecks)
      val (w0, w1) = (x.word0, x.word1)
      val leaf = w0(31)
      val indexTooWide = Mux(leaf, highBitsSet(w1, cfg.triIndexBits), highBitsSet(w1, cfg.nodeIndexBits))
      // Nori: an inner node's word0 is its split axis, 0..2. Wide: an inner
      // child's word0 is 0, an empty slot's is EmptySlot; nothing else is valid.
      val badKind = cfg.layout match {
        case BvhLayout.Nori    => !leaf && (w0(30, 0) > 2.U)
        case _: BvhLayout.Wide => !leaf && w0 =/= 0.U && w0 =/= EmptySlot.U
      }
      c.present := present(cfg, w0)
      c.indexBad := indexTooWide || badKind
      c.leafTooBig := leaf && (w0(30, 0) > cfg.maxLeafSize.U)
      // A NaN or infinite bound would make the slab test miss (or hit)
      // silently: nori-bridge writes only finite bounds, so it is bad data.
      c.badBox := w.gridBad.getOrElse((x.lo ++ x.hi).map(ErrorFlags.nonFinite).reduce(_ || _))
      c
    })
  }

  /** The node's error flags from its slots' checks: only used slots can flag. */
  def errors(checks: Seq[SlotChecks]): UInt = checks.map { c =>
    Mux(c.present && c.indexBad, ErrorFlags.bit(ErrorFlags.IndexOverflow), 0.U) |
      Mux(c.present && c.leafTooBig, ErrorFlags.bit(ErrorFlags.LeafTooBig), 0.U) |
      Mux(c.present && c.badBox, ErrorFlags.bit(ErrorFlags.BadSceneData), 0.U)
  }.reduce(_ | _)
}
