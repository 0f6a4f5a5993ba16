package rtaccel.leaf

import chisel3._
import chisel3.util._
import rtaccel.fp.FpOrder
import rtaccel.{AccelConfig, ErrorFlags}

/** LeafIntersect's per-ID tables, as the read-ahead reads them. */
final case class LeafTables(
    hasHit: Vec[Bool],
    occluded: Vec[Bool],
    errors: Vec[UInt],
    counts: OutstandingCounts,
    bestMem: Mem[BestHit],

    /** The best table's write in flight: it lands a cycle after its answer, at the end of this cycle. */
    bestWrite: Valid[BestWrite]
) {

  /** The best hit of an ID as it stands, the write in flight forwarded. */
  def best(id: UInt): BestHit = Mux(bestWrite.valid && bestWrite.bits.id === id, bestWrite.bits.hit, bestMem.read(id))
}

/** One cycle's writes to those tables (a Wire: the reduce stage's writes depend on the read-ahead's registers).
  * A clear is applied after the others, as in the tables.
  */
class LeafWrites(cfg: AccelConfig) extends Bundle {

  /** A triangle request for `incId`. */
  val inc = Bool()
  val incId = UInt(cfg.rayIdBits.W)

  /** An answer for `doneId` is reduced: it sets the has-hit flag (`anyHit`), the occluded flag (`occludes`),
    * adds `errors`, and replaces the best hit with `best` (`update`).
    */
  val reduce = Bool()
  val doneId = UInt(cfg.rayIdBits.W)
  val anyHit = Bool()
  val occludes = Bool()
  val errors = UInt(ErrorFlags.width.W)
  val update = Bool()
  val best = new BestHit(cfg)
  val clear = Valid(UInt(cfg.rayIdBits.W))
}

/** The reduce stage's view of the answered ray's table entries, read a cycle
  * ahead of it: each register holds the entry for the ID the reduce stage
  * takes next, as it will stand after the writes of the cycles in between,
  * so the reduce stage reads registers, never a 1-of-`numRayIds` table.
  *
  * A 1-of-n read of a table in one stage maps to a chain of up to six
  * LUT/MUXF7/MUXF8 levels (the unit's longest path, 6.2 to 9.3 ns by the
  * netlist, docs/fmax.md). So at `pre2` each group of 16 IDs selects its entry
  * for `pre2Id` into a register, and at `pre`, `preId` being the same ID a
  * cycle later, the groups' entries are ORed ([[GroupedRead]]). Every write to
  * the ID in either cycle is forwarded: the pre2 cycle's from registers beside
  * the groups', the pre cycle's as it happens; a clear is applied last in each
  * cycle. The best hit is read at `pre` alone (it is a memory, not a table of
  * registers), the write still in flight forwarded ([[LeafTables.best]]);
  * this cycle's own write becomes the next cycle's write in flight, and is
  * taken from it there. When pre2 carries no answer, nothing reads the result.
  */
class LeafReadAhead(cfg: AccelConfig, t: LeafTables, w: LeafWrites, pre2Id: UInt, preId: UInt, incIsPre: Bool) {
  private val toPre2 = w.doneId === pre2Id
  private val clrPre2Reg = RegNext(w.clear.valid && w.clear.bits === pre2Id)
  private val incPre2Reg = RegNext(w.inc && w.incId === pre2Id)
  private val decPre2Reg = RegNext(w.reduce && toPre2)
  private val hitPre2Reg = RegNext(w.anyHit && toPre2)
  private val occPre2Reg = RegNext(w.occludes && toPre2)
  private val errPre2Reg = RegNext(Mux(w.reduce && toPre2, w.errors, 0.U))
  private val outIsPre = GroupedRead(t.counts.flags, pre2Id)
  private val hasHitPre = !clrPre2Reg && (GroupedRead(t.hasHit.map(_.asUInt), pre2Id).asBool || hitPre2Reg)
  private val occPre = !clrPre2Reg && (GroupedRead(t.occluded.map(_.asUInt), pre2Id).asBool || occPre2Reg)
  private val errPre = Mux(clrPre2Reg, 0.U, GroupedRead(t.errors, pre2Id) | errPre2Reg)

  private val toPre = w.doneId === preId
  private val clrPre = w.clear.valid && w.clear.bits === preId

  /** The answered ray's outstanding count is 1: this answer is its last. */
  val lastReg: Bool = Reg(Bool())
  // outstanding + (inc - dec over both cycles) === 1: the flag of the count that needs, of the count as the
  // pre2 cycle began (0 to 3, since the net change is -2 to 2), so no carry chain or compare follows the read.
  // `incIsPre`: `w.incId === preId`, compared a cycle ahead by the caller (from the issuing ID's register
  // through this compare into `lastReg` was 5.24 ns).
  private val net = incPre2Reg.asUInt +& (w.inc && incIsPre).asUInt
  private val drop = decPre2Reg.asUInt +& (w.reduce && toPre).asUInt
  lastReg := MuxLookup(Cat(net, drop), false.B)(
    Seq(
      Cat(0.U(2.W), 0.U(2.W)) -> outIsPre(1),
      Cat(1.U(2.W), 1.U(2.W)) -> outIsPre(1),
      Cat(2.U(2.W), 2.U(2.W)) -> outIsPre(1),
      Cat(1.U(2.W), 0.U(2.W)) -> outIsPre(0),
      Cat(2.U(2.W), 1.U(2.W)) -> outIsPre(0),
      Cat(0.U(2.W), 1.U(2.W)) -> outIsPre(2),
      Cat(1.U(2.W), 2.U(2.W)) -> outIsPre(2),
      Cat(0.U(2.W), 2.U(2.W)) -> outIsPre(3)
    )
  )
  val hasHitReg: Bool = RegNext(!clrPre && (hasHitPre || (w.anyHit && toPre)))
  // The best hit: read at `pre` with the write in flight forwarded, and registered with its order key. An
  // answer in the pre cycle that replaces this ray's best becomes the next cycle's write in flight, and the
  // reduce stage compares with that one instead. Both compares are made and the result selected by a
  // register, so no select sits between the closer-hit compare and the registers it decides (a select of
  // the keys there, by the compare's own result a cycle before, mapped to 5.6 to 6.5 ns). `toPre` for that
  // select is compared a cycle ahead: the reduce stage's ID is the pre stage's a cycle before, and the pre
  // stage's the pre2 stage's, whenever both carry answers (the only cycles that read the select).
  private val base = t.best(preId)
  private val baseReg = RegNext(base)
  // A best hit's order key: its distance's key (FpOrder.key) with its triangle below it, so "smaller t, ties to
  // the smaller prim" is one unsigned compare, one carry chain. As a compare of the keys and one of the prims
  // combined after their chains, it mapped to four LUTs after the prims' chain (5.55 ns, docs/fmax.md).
  private def orderKey(tKey: UInt, prim: UInt): UInt = Cat(tKey, prim)
  private def keyOf(b: BestHit): UInt = orderKey(FpOrder.key(cfg.triFloat, b.t), b.prim)
  // The table's entry is registered as read and its key formed after the register: the read is block RAM, and
  // its clock-to-out through the forward's select and the key's sign flips into a key register was the core
  // control's longest path (5.22 ns, docs/fmax.md). After the register the flips sit in the compare's first LUTs.
  private val baseKey = keyOf(baseReg)
  private val toPreAheadReg = RegNext(preId === pre2Id)
  // "The previous answer was this ray's and replaced its best" is the write in flight's valid (a register)
  // and the same-ray compare, registered again, ANDed after their registers: so the closer-hit compare ends in
  // the write's valid alone. Registered as one bit, the AND with the compare's result mapped to one LUT more
  // after its carry chain (5.41 ns).
  private val sameRayReg = RegNext(toPreAheadReg)
  private val fromWrite = t.bestWrite.valid && sameRayReg
  private val writeKeyReg = RegNext(keyOf(w.best))
  assert(
    !w.reduce || fromWrite === (t.bestWrite.valid && t.bestWrite.bits.id === w.doneId),
    "leaf_old_write: the reduce stage compares with the wrong best hit (the write in flight or the table's)"
  )
  assert(
    !w.reduce || writeKeyReg === keyOf(t.bestWrite.bits.hit),
    "leaf_old_key: the best distance's key is stale"
  )

  /** An answer at distance key `tKey` (FpOrder.key) and triangle `prim` is closer than the answered ray's
    * best hit before it: smaller t, ties to the smaller prim (a total order). The caller ORs in "no hit yet".
    */
  def closer(tKey: UInt, prim: UInt): Bool = {
    val key = orderKey(tKey, prim)
    Mux(fromWrite, key < writeKeyReg, key < baseKey)
  }
  val occludedReg: Bool = RegNext(!clrPre && (occPre || (w.occludes && toPre)))
  val errorsReg: UInt = RegNext(Mux(clrPre, 0.U, errPre | Mux(w.reduce && toPre, w.errors, 0.U)))
}
