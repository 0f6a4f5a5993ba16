package rtaccel.formal

import rtaccel.RtAccel

/** Writes the system proofs' SystemVerilog for `make formal-system`:
  * formal_<case>.sv (FormalSystemTop, with the real RtAccel inside),
  * stub_<case>.sv (FormalCoreStub under RtAccel's module name, read over it),
  * formal_<case>.props and system-cases.txt (name, depth, bound for RAY_COUNT = 1).
  *
  * Usage: EmitFormalSystem --out build/formal [--bound-cut N]  (N: a probe's cut bound for every RAY_COUNT)
  */
object EmitFormalSystem {
  def main(args: Array[String]): Unit = {
    val out = args.sliding(2).collectFirst { case Array("--out", d) => java.nio.file.Paths.get(d) }
      .getOrElse(throw new IllegalArgumentException("EmitFormalSystem: usage: --out <dir>"))
    java.nio.file.Files.createDirectories(out)
    java.nio.file.Files.writeString(out.resolve("FormalAnySeq.v"), FormalAnySeq.verilog)
    val dp = FormalSystemTop.datapath
    val lines = for (c <- SystemCase.all) yield {
      val b = (r: Int) => SystemBound(c, r).map(_.cycles).sum
      val sv = ForYosys(rtaccel.tools.Synth.emit(new FormalSystemTop(c, b, dp)))
      val core = "module (RtAccel_[A-Za-z0-9_]+)\\(".r.findFirstMatchIn(sv).map(_.group(1))
        .getOrElse(throw new IllegalStateException("EmitFormalSystem: no RtAccel module in the system's SystemVerilog"))
      val stub = ForYosys(rtaccel.tools.Synth.emit(new FormalCoreStub(c.sys.core, core, c.env.stall)))
      java.nio.file.Files.writeString(out.resolve(s"formal_${c.name}.sv"), sv)
      java.nio.file.Files.writeString(out.resolve(s"stub_${c.name}.sv"), stub)
      // The real core's assertions are in the system's SystemVerilog but not in the model (the stub replaces it).
      val coreOnly = ForYosys.names(ForYosys(rtaccel.tools.Synth.emit(new RtAccel(c.sys.core, dp)))).toSet
      val props = (ForYosys.names(sv).filterNot(coreOnly) ++ ForYosys.names(stub)).distinct
      java.nio.file.Files.writeString(out.resolve(s"formal_${c.name}.props"), props.mkString("", "\n", "\n"))
      for (r <- 1 to c.env.maxRays)
        println(s"EmitFormalSystem: ${c.name} RAY_COUNT $r: bound ${b(r)} = " + SystemBound(c, r).map(t =>
          s"${t.name} ${t.cycles}"
        ).mkString(" + "))
      s"${c.name} ${c.depth} ${b(1)}\n"
    }
    java.nio.file.Files.writeString(out.resolve("system-cases.txt"), lines.mkString)
    // The system's units alone (FormalSystemUnits), each checked past its derived bound: make formal-system-units.
    val units = for (u <- SystemCase.units) yield {
      val sv = ForYosys(rtaccel.tools.Synth.emit(u.top()))
      java.nio.file.Files.writeString(out.resolve(s"formal_${u.name}.sv"), sv)
      java.nio.file.Files.writeString(
        out.resolve(s"formal_${u.name}.props"),
        ForYosys.names(sv).mkString("", "\n", "\n")
      )
      println(s"EmitFormalSystem: unit ${u.name} bound ${u.bound} (${u.terms}), depth ${u.depth}")
      s"${u.name} ${u.depth} ${u.bound}\n"
    }
    java.nio.file.Files.writeString(out.resolve("system-units.txt"), units.mkString)
  }
}
