package rtaccel.formal

import rtaccel.fp.FloatFormat
import rtaccel.tools.Synth
import rtaccel.{AccelConfig, BvhLayout}

import java.nio.file.{Files, Paths}

/** One proof: a small configuration, its datapath latencies, its environment and BMC depth. */
final case class FormalCase(name: String, cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv, depth: Int)

object FormalCase {
  /** Narrow everything the properties do not depend on: 2 nodes, 2 triangle
    * slots, leaves of up to 2 triangles, a 6-bit float, 8-bit addresses. */
  private def small(ids: Int): AccelConfig = AccelConfig(numRayIds = ids, stackDepth = 2, maxNodes = 2, maxTriangles = 2,
    maxLeafSize = 2, boxFloat = FloatFormat(3, 2), triFloat = FloatFormat(3, 2), addrBits = 8, layout = BvhLayout.Wide(2))
  private val dp = new FormalDatapath(prepLatency = 1, boxLatency = 2, primLatency = 2)

  val all: Seq[FormalCase] = Seq(
    FormalCase("n2", small(2), dp, FormalEnv(memLatency = 3, memStall = 1, hitStall = 2, responseBound = 80), depth = 28),
    FormalCase("n4", small(4), dp, FormalEnv(memLatency = 3, memStall = 1, hitStall = 2, responseBound = 160), depth = 20)
  )
}

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
      val sv = ForYosys(Synth.emit(new FormalTop(c.cfg, c.dp, c.env)))
      Files.writeString(out.resolve(s"formal_${c.name}.sv"), sv)
      Files.writeString(out.resolve(s"formal_${c.name}.props"), ForYosys.names(sv).mkString("", "\n", "\n"))
      println(s"EmitFormal: ${out.resolve(s"formal_${c.name}.sv")}")
    }
    Files.writeString(out.resolve("cases.txt"), FormalCase.all.map(c => s"${c.name} ${c.depth} ${c.env.responseBound}\n").mkString)
  }
}
