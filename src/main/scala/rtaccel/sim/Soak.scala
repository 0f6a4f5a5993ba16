package rtaccel.sim

import chisel3._
import chiseltest._
import firrtl2.options.TargetDirAnnotation
import rtaccel.bvh.BvhLayout
import rtaccel.sim.mem.{Latency, MemoryKind, MemoryParams}

import java.nio.file.{Files, Paths}
import scala.util.Random

/** `make soak`: the control path under random back-pressure for a long time.
  * For each node layout and each ray-ID count, batches of random rays run
  * through the RTL (FieldDatapath's cheap arithmetic, synthetic trees deeper
  * than the stack, NaN/infinite rays) until at least `--cycles` cycles have
  * passed, each batch in an environment drawn afresh: memory latency 1..300,
  * in or out of order, 1..64 outstanding requests, refusals on every port,
  * gaps in the offered rays, refused hits. Every ray must come back exactly
  * once (AccelHarness stops at once on a lost, duplicated or `broken` ray, or
  * a deadlock) and bit-exact with the golden traversal. Writes
  * build/soak/soak.json and prints one line per configuration.
  */
object Soak {
  def main(args: Array[String]): Unit = {
    val kv = args.grouped(2).collect { case Array(k, v) => k -> v }.toMap
    val cycles = kv.get("--cycles").map(_.toLong).getOrElse(1000000L)
    val layouts = kv.get("--layouts").map(_.split(',').toSeq.map(BvhLayout.parse)).getOrElse(BvhLayout.all)
    val idCounts = kv.get("--ids").map(_.split(',').toSeq.map(_.toInt)).getOrElse(Seq(2, 4, 64))
    val seed = kv.get("--seed").map(_.toLong).getOrElse(System.nanoTime())
    println(s"soak: seed $seed (replay: make soak SOAK_SEED=$seed), $cycles cycles per configuration")
    val rnd = new Random(seed)
    val rows = for (layout <- layouts; ids <- idCounts) yield {
      val cfg = ControlWorkload.config(layout, ids)
      val annos = Seq(
        VerilatorBackendAnnotation,
        chiseltest.internal.CachingAnnotation,
        TargetDirAnnotation(s"build/soak/SimTop_field_k${cfg.boxLanes}_n$ids")
      )
      var (simCycles, rays, batches, errors) = (0L, 0L, 0, 0L)
      val t0 = System.nanoTime()
      RawTester.test(new SimTop(cfg, FieldDatapath), annos) { dut =>
        while (simCycles < cycles) {
          val (img, _) = ControlWorkload.treeOf(layout, new Random(rnd.nextLong()))
          val batch = ControlWorkload.makeRays(rnd, 200 + rnd.nextInt(800))
          // On chip a port has a fixed latency; behind the shared DRAM any range.
          val onChip = rnd.nextBoolean()
          def mem() = MemoryParams(
            if (onChip || rnd.nextBoolean()) Latency.Fixed(1 + rnd.nextInt(300))
            else Latency.Uniform(1, 1 + rnd.nextInt(300)),
            maxOutstanding = 1 + rnd.nextInt(64),
            inOrder = rnd.nextInt(4) == 0
          )
          val env = Environment(
            mem(),
            mem(),
            if (onChip) MemoryKind.OnChip else MemoryKind.Ddr(),
            rayGap = rnd.nextDouble() * 0.6,
            hitRefuse = rnd.nextDouble() * 0.8,
            memRefuse = rnd.nextDouble() * 0.5,
            seed = rnd.nextLong()
          )
          dut.reset.poke(true.B); dut.clock.step(); dut.reset.poke(false.B)
          // 64 rays sharing one outstanding request at 300 cycles of latency can go
          // 10^5 cycles with no ray leaving: the deadlock alarm waits far longer.
          val run = AccelHarness.run(dut, img, batch, env, stallLimit = 2000000)
          ControlWorkload.check(cfg, img, batch, run.hits, s"soak ${layout.name} ids=$ids batch $batches")
          simCycles += run.cycles; rays += batch.size; batches += 1
          errors += run.hits.count(_.errors != 0)
        }
      }
      val secs = (System.nanoTime() - t0) / 1e9
      println(
        f"soak: layout ${layout.name}%-4s ids $ids%2d: $simCycles%,d cycles, $rays%,d rays in $batches batches, " +
          f"every ray answered once and golden-exact ($errors%,d with error flags), $secs%.0f s"
      )
      ujson.Obj(
        "layout" -> layout.name,
        "ids" -> ids,
        "cycles" -> simCycles.toDouble,
        "rays" -> rays.toDouble,
        "batches" -> batches,
        "errorRays" -> errors.toDouble,
        "seconds" -> secs
      )
    }
    Files.createDirectories(Paths.get("build/soak"))
    Files.writeString(
      Paths.get("build/soak/soak.json"),
      ujson.write(ujson.Obj("seed" -> seed.toDouble, "runs" -> ujson.Arr(rows: _*)), indent = 2)
    )
    println("soak: wrote build/soak/soak.json")
  }
}
