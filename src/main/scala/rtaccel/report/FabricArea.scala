package rtaccel.report

import rtaccel.leaf.LeafIntersect
import rtaccel.mem.MemPortParams
import rtaccel.system.{MemoryFabric, SystemConfig}
import rtaccel.tools.Synth
import rtaccel.traversal.PrepFetch

import java.nio.file.{Files, Paths}

/** Yosys area of MemoryFabric for the default system's clients (two cores'
  * node and triangle ports and a 64-byte ray-line reader), with the node
  * store of `args(0)` KiB (0: none, the logic alone), into build/fabric-area/.
  */
object FabricArea extends App {
  val kib = args.headOption.map(_.toInt).getOrElse(0)
  val sys = SystemConfig(nodeStoreBytes = kib * 1024)
  val node = PrepFetch.port(sys.core).copy(tagBits = sys.core.rayIdBits + 1)
  val ports =
    Seq.fill(sys.cores)(Seq(node, LeafIntersect.port(sys.core))).flatten :+ MemPortParams(sys.axiAddrBits, 4, 64)
  val flags = Seq.fill(sys.cores)(Seq(true, false)).flatten :+ false
  val dir = Paths.get("build/fabric-area")
  Files.createDirectories(dir)
  val sv = dir.resolve(s"fabric_$kib.sv")
  Files.writeString(sv, Synth.emit(new MemoryFabric(sys, ports, flags)))
  val top = Synth.modules(Files.readString(sv)).last
  val a = Synth.yosys(sv, top)
  println(s"$top: ${a.lutSites} LUT (${a.lutMemory} as memory), ${a.ff} FF, ${a.bram36} BRAM36, ${a.carry} CARRY4")
}
