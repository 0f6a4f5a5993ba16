package rtaccel.formal

import rtaccel.fp.FloatFormat
import rtaccel.tools.Synth
import rtaccel.AccelConfig
import rtaccel.bvh.BvhLayout

import java.nio.file.{Files, Paths}

/** One proof: a small configuration, its datapath latencies, its environment
  * and BMC depth; `deep` cases run in `make formal-deep`, not `make formal`.
  */
final case class FormalCase(
    name: String,
    cfg: AccelConfig,
    dp: FormalDatapath,
    env: FormalEnv,
    depth: Int,
    deep: Boolean = false
) {

  /** Derived, never chosen: ResponseBound. */
  val responseBound: Int = ResponseBound(cfg, dp, env)
}

object FormalCase {

  /** Narrow everything the properties do not depend on: 2 nodes, 2 triangle
    * slots, leaves of up to 2 triangles, a 6-bit float, 8-bit addresses. */
  private[formal] def small(ids: Int): AccelConfig = AccelConfig(
    numRayIds = ids,
    stackDepth = 2,
    maxNodes = 2,
    maxTriangles = 2,
    maxLeafSize = 2,
    boxFloat = FloatFormat(3, 2),
    triFloat = FloatFormat(3, 2),
    addrBits = 8,
    layout = BvhLayout.Wide(2)
  )
  private val dp = new FormalDatapath(prepLatency = 1, boxLatency = 2, primLatency = 2)
  private val env = FormalEnv(memLatency = 3, memStall = 1, hitStall = 2)

  /** LeafIntersect's bounded response: everything as fast as it can be
    * (latencies 1, memory answering the next cycle, never stalling, leaves
    * of one triangle); in the n2 environment pdr finds no verdict in 5
    * minutes (docs/formal.md). */
  private val fast = new FormalDatapath(prepLatency = 1, boxLatency = 1, primLatency = 1)
  private val fastEnv = FormalEnv(memLatency = 1, memStall = 0, hitStall = 0)
  private val tiny = small(2).copy(maxLeafSize = 1)

  val all: Seq[FormalCase] = Seq(
    FormalCase("n2", small(2), dp, env, depth = 36),
    FormalCase("n4", small(4), dp, env, depth = 18)
  )

  /** Each unit alone, checked by BMC to 8 steps past its derived bound (a ray
    * entering in the first 8 steps is followed until it leaves) in `make
    * formal-deep`, and for all time by pdr in `make formal-induction`. */
  val units: Seq[UnitCase] = {
    def fetch(name: String, cfg: AccelConfig, e: FormalEnv) = {
      val bound = UnitBound.fetch(cfg, e)
      UnitCase(name, () => new FormalFetchTop(cfg, e, bound, name), bound, bound + 8, deep = true)
    }
    def leaf(name: String, cfg: AccelConfig, d: FormalDatapath, e: FormalEnv) = {
      val bound = UnitBound.leaf(cfg, d, e)
      UnitCase(name, () => new FormalLeafTop(cfg, d, e, bound, name), bound, bound + 8, deep = true)
    }
    Seq(fetch("fetch2", small(2), env), leaf("leaf2f", tiny, fast, fastEnv))
  }
}

/** A per-unit bounded-response proof: its harness, derived bound and depth. */
final case class UnitCase(
    name: String,
    top: () => chisel3.RawModule,
    bound: Int,
    depth: Int,
    deep: Boolean = false,
    terms: String = ""
)

/** Writes each proof's SystemVerilog (formal_<name>.sv), FormalAnySeq.v and
  * cases.txt (name, depth per line) for mk/formal.mk.
  *
  * Usage: EmitFormal --out build/formal
  */
object EmitFormal {
  def main(args: Array[String]): Unit = {
    val out = args.sliding(2).collectFirst { case Array("--out", d) => Paths.get(d) }
      .getOrElse(throw new IllegalArgumentException("EmitFormal: usage: --out <dir>"))
    Files.createDirectories(out)
    Files.writeString(out.resolve("FormalAnySeq.v"), FormalAnySeq.verilog)
    for (c <- FormalCase.all) {
      val sv = ForYosys(Synth.emit(new FormalTop(c.cfg, c.dp, c.env, c.responseBound, c.name)))
      Files.writeString(out.resolve(s"formal_${c.name}.sv"), sv)
      Files.writeString(out.resolve(s"formal_${c.name}.props"), ForYosys.names(sv).mkString("", "\n", "\n"))
      println(s"EmitFormal: ${out.resolve(s"formal_${c.name}.sv")}")
    }
    // Per-unit bounded response (FormalUnits): checked past the derived bound.
    val units = FormalCase.units
    for (u <- units) {
      val sv = ForYosys(Synth.emit(u.top()))
      Files.writeString(out.resolve(s"formal_${u.name}.sv"), sv)
      Files.writeString(out.resolve(s"formal_${u.name}.props"), ForYosys.names(sv).mkString("", "\n", "\n"))
      println(s"EmitFormal: ${u.name} bound = ${u.bound}, depth ${u.depth}")
    }
    // Unit proofs for make formal-induction: the free list alone, 2 and 4 IDs.
    for (n <- Seq(2, 4)) {
      val sv = ForYosys(Synth.emit(new FormalFreeList(n)))
      Files.writeString(out.resolve(s"formal_ids$n.sv"), sv)
      Files.writeString(out.resolve(s"formal_ids$n.props"), ForYosys.names(sv).mkString("", "\n", "\n"))
    }
    def list(cs: Seq[FormalCase]) = cs.map(c => s"${c.name} ${c.depth} ${c.responseBound}\n").mkString
    def unitList(us: Seq[UnitCase]) = us.map(u => s"${u.name} ${u.depth} ${u.bound}\n").mkString
    Files.writeString(
      out.resolve("cases.txt"),
      list(FormalCase.all.filterNot(_.deep)) + unitList(units.filterNot(_.deep))
    )
    Files.writeString(
      out.resolve("cases-deep.txt"),
      list(FormalCase.all.filter(_.deep)) + unitList(units.filter(_.deep))
    )
    for (c <- FormalCase.all) {
      val ts = ResponseBound.terms(c.cfg, c.dp, c.env)
      println(s"EmitFormal: ${c.name} responseBound = ${c.responseBound} = " + ts.map(t =>
        s"${t.name} ${t.cycles}"
      ).mkString(" + "))
    }
  }
}
