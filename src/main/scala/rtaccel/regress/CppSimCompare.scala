package rtaccel.regress

import chisel3.Data
import chiseltest._
import firrtl2.options.TargetDirAnnotation
import rtaccel.scene.ScenePackage
import rtaccel.system.SystemConfig
import rtaccel.sim.{SystemHarness, SystemSimTop}
import rtaccel.sim.axi.AxiMemoryParams

import java.nio.file.{Files, Paths}
import scala.sys.process._

/** The two harnesses of the system top side by side on the same rays and
  * memory settings: the chiseltest one (SystemHarness + AxiMemoryModel) and
  * the C++ one (rtaccel-sim: librtaccel + the C++ twin of AxiMemoryModel).
  * Same buffer layout as librtaccel's (scene at 0x10000000, rays and hits each
  * at the next 64-byte boundary). Prints both batches' CYCLES, their speed
  * (simulated cycles per wall second and per CPU second, user + sys of the
  * process: the machine is shared) and whether every hit record agrees;
  * writes OUT/compare.json. Exit 1 if any hit record or the batch's CYCLES
  * differ (`make cppsim-compare`).
  *
  * usage: CppSimCompare --package DIR --out DIR [--rays N] [--reorder 0|1]
  */
object CppSimCompare {

  /** CPU time of this process (every thread: the JVM's and the Verilated model's, which chiseltest loads in-process). */
  private def cpuNanos(): Long = java.lang.management.ManagementFactory.getOperatingSystemMXBean match {
    case b: com.sun.management.OperatingSystemMXBean => b.getProcessCpuTime
    case _ => throw new IllegalStateException("no process CPU time on this JVM")
  }

  def main(args: Array[String]): Unit = { val ok = Cli.orExit(run(args)); sys.exit(if (ok) 0 else 1) }

  def run(args: Array[String]): Boolean = {
    val kv = args.toSeq.grouped(2).collect { case Seq(k, v) => k -> v }.toMap
    val a = RegressArgs(Paths.get(kv("--package")), Paths.get(kv("--out")))
    val reorder = kv.getOrElse("--reorder", "1") == "1"
    val pkg = ScenePackage.load(a.pkg)
    val rays = kv.get("--rays").fold(pkg.rays)(n => pkg.rays.take(n.toInt))
    val cfg = Regress.config(a, pkg)
    Files.createDirectories(a.out)
    DatapathChoice.resolve(RegressArgs.formats(a)._1, RegressArgs.formats(a)._2, a.triangle, a.rounding) match {
      case c: Chosen[t, s] =>
        val dp = c.asInstanceOf[Chosen[Data, s]].dp
        // The build `make regress SIM=cpp` uses (clang), so the speeds compared are the regression's.
        val dir = CppSim.build(cfg, dp, clang = CppSim.useClang)
        // C++ first (quick), then chiseltest.
        val cmd = Seq(
          dir.resolve("rtaccel-sim").toString,
          "--package",
          a.pkg.toAbsolutePath.toString,
          "--out",
          a.out.toAbsolutePath.toString,
          "--rays",
          rays.size.toString,
          "--reorder",
          if (reorder) "1" else "0"
        )
        if (cmd.! != 0) throw new IllegalStateException("rtaccel-sim failed")
        val cppHits = CppSim.readHits(a.out.resolve("hits.bin"), rays.size)
        val sim = ujson.read(Files.readString(a.out.resolve("sim.json")))
        val base = 0x10000000L
        def up(x: Long) = (x + 63) / 64 * 64
        val rayBase = base + up(pkg.image.bytes.length.toLong)
        val lay = SystemHarness.Layout(base, rayBase, up(rayBase + SystemConfig.RayBytes.toLong * rays.size))
        val annos = Seq(
          VerilatorBackendAnnotation,
          chiseltest.internal.CachingAnnotation,
          TargetDirAnnotation(
            Paths.get("").toAbsolutePath.relativize(CppSim.simDir(dp.name, cfg, 1).resolve("chiseltest")).toString
          )
        )
        var line = ""
        var ok = false
        RawTester.test(new SystemSimTop(SystemConfig(core = cfg, cores = 1), dp), annos) { dut =>
          val h = new SystemHarness(dut, AxiMemoryParams(reorder = reorder))
          h.put(lay.sceneBase, pkg.image.bytes)
          h.putRays(lay.rayBase, rays)
          val code = h.loadScene(lay.sceneBase)
          require(code == 0, s"SCENE_ERROR_CODE $code")
          val c0 = h.cycle
          val t0 = System.nanoTime()
          val cpu0 = cpuNanos()
          val bar = new Progress("chiseltest:", rays.size)
          h.runBatch(lay.rayBase, rays.size, lay.hitBase, 50000000L, bar.update)
          bar.finish(rays.size)
          val cpu = (cpuNanos() - cpu0) / 1e9
          val secs = (System.nanoTime() - t0) / 1e9
          val cycles = h.read64("CYCLES")
          val hits = rays.indices.map(i => h.hitRecord(lay.hitBase, i)._1)
          val same = hits.zip(cppHits).count { case (x, y) => x == y }
          val cppCycles = sim("batchCycles").num.toLong
          val simulated = h.cycle - c0
          line =
            s"chiseltest: batch CYCLES $cycles, $simulated cycles simulated (the batch's register accesses included) in " +
              f"$secs%.2f s wall, $cpu%.2f s CPU: ${simulated / secs}%.0f cycles/s, ${simulated / cpu}%.0f cycles per CPU second\n" +
              s"cpp:        batch CYCLES $cppCycles, ${sim("simulation").obj.mkString(", ")}\n" +
              s"hit records equal: $same of ${rays.size}; batch CYCLES ${if (cycles == cppCycles) "equal"
                else s"differ by ${cppCycles - cycles}"}; reorder=$reorder"
          Files.writeString(
            a.out.resolve("compare.json"),
            ujson.write(
              ujson.Obj(
                "rays" -> rays.size,
                "reorder" -> reorder,
                "hitRecordsEqual" -> same,
                "chiseltest" -> ujson.Obj(
                  "batchCycles" -> cycles.toDouble,
                  "simulatedCycles" -> simulated.toDouble,
                  "wallSeconds" -> secs,
                  "cpuSeconds" -> cpu,
                  "cyclesPerSecond" -> simulated / secs,
                  "cyclesPerCpuSecond" -> simulated / cpu
                ),
                "cpp" -> ujson.Obj("batchCycles" -> cppCycles.toDouble, "simulation" -> sim("simulation"))
              ),
              indent = 2
            )
          )
          ok = same == rays.size && cycles == cppCycles
        }
        println(line)
        Files.writeString(a.out.resolve("compare.txt"), line + "\n")
        ok
    }
  }
}
