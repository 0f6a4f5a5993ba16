package rtaccel.study

import rtaccel.datapath.{BoxRounding, FloatDatapath, FloatGolden, TriangleTest}
import rtaccel.fp.FloatFormat
import rtaccel.golden.TraversalGolden
import rtaccel.regress.{Bridge, Cli}
import rtaccel.scene.ScenePackage
import rtaccel.bench.Bench

import java.nio.file.{Files, Paths}
import scala.collection.mutable

/** Hit rates of the two node-store designs on the regression
  * scenes, from the golden walk's node fetches (the hardware's node reads,
  * one per node test):
  *  - preload: a node read hits when the node lies in the first S bytes of
  *    the node array, in image order (as nori-bridge writes it: breadth
  *    first for the wide layouts, depth first for nori) or breadth-first;
  *  - cache: an LRU set-associative cache of S bytes (64-byte lines, 4 ways),
  *    a read hits when every line of its node is present; rays are
  *    interleaved 64 at a time, one fetch each in turn, as 64 ray IDs in
  *    flight would (an estimate: real interleaving depends on timing); cold
  *    (empty at the start) and warm (odd rays after the even ones filled it).
  * Writes a markdown table to build/node-store/study.md (pasted into
  * docs/node-store.md).
  */
object NodeStoreStudy {
  val SizesKiB: Seq[Int] = Seq(16, 64, 256, 512, 1024, 2048)
  val Layouts: Seq[String] = Seq("4", "8", "4q", "8q", "nori")
  val InFlight = 64

  def main(args: Array[String]): Unit = Cli.orExit {
    // Arguments: [maxRays] [packages root]: with a root (e.g. build/bench, laid out <layout>/<run>),
    // packages already compiled there are read instead of compiled again.
    val maxRays = args.headOption.map(_.toInt).getOrElse(2048)
    val from = args.lift(1).map(Paths.get(_))
    val bridge = Paths.get("nori-bridge/target/release/nori-bridge")
    val root = Paths.get("build/node-store")
    val dp = FloatDatapath(FloatFormat.FP32, TriangleTest.parse("watertight"), BoxRounding.parse("conservative"))
    val golden = FloatGolden(dp)
    val rows = mutable.ArrayBuffer.empty[String]
    for (layout <- Layouts; run <- Bench.Runs) {
      val dir = from.getOrElse(root).resolve(layout).resolve(run.name)
      if (from.isEmpty) Bridge.compile(
        bridge,
        Paths.get(run.xml),
        dir,
        run.rays,
        bvh = Option.when(layout != Bench.DefaultLayout)(layout)
      )
      val p = ScenePackage.load(dir)
      val cfg = Bench.configFor(layout)
      val stride = (p.rays.size + maxRays - 1) / maxRays
      val rays = p.rays.indices.by(stride.max(1)).map(p.rays)
      val traces = rays.map { r =>
        val b = mutable.ArrayBuilder.make[Long]
        TraversalGolden.trace(cfg, p.image, golden, r, b += _)
        b.result()
      }
      val nb = p.image.nodeBytes.toInt
      val bfs = NodeOrder.breadthFirst(p.image)
      val order = NodeOrder.name(p.image, bfs)
      val fetches = traces.map(_.length.toLong).sum
      val cells = SizesKiB.map { kib =>
        val s = kib * 1024L
        def rate(hit: Long => Boolean) = traces.map(_.count(hit).toLong).sum.toDouble / fetches
        val dfs = rate(i => (i + 1) * nb <= s)
        val bf = rate(i => (bfs(i.toInt) + 1) * nb <= s)
        val (cold, warm) = cacheRate(traces, s, nb, p.image.nodeOffset)
        f"${100 * dfs}%.1f / ${100 * bf}%.1f / ${100 * cold}%.1f / ${100 * warm}%.1f"
      }
      val arrayKiB = p.image.nodeCount * nb / 1024.0
      rows += s"| ${run.name} | $layout | $order | ${rays.size} | ${f"${fetches.toDouble / rays.size}%.1f"} | ${f"$arrayKiB%.0f"} | ${cells.mkString(" | ")} |"
      println(rows.last)
    }
    val md = new StringBuilder
    md ++= s"Node reads that hit, in percent: preload in image order / preload breadth-first / LRU cache " +
      s"(64 B lines, 4-way, $InFlight rays interleaved) cold / warm, per store size.\n\n"
    md ++= s"| rays | layout | image order | rays walked | node reads/ray | node array KiB | ${SizesKiB.map(k => s"$k KiB").mkString(" | ")} |\n"
    md ++= s"| --- | --- | --- | ---: | ---: | ---: | ${SizesKiB.map(_ => "---:").mkString(" | ")} |\n"
    rows.foreach(r => md ++= r + "\n")
    Files.createDirectories(root)
    Files.writeString(root.resolve("study.md"), md.toString)
    println(s"node-store study: wrote ${root.resolve("study.md")}")
  }

  /** Hit rates of an LRU cache of `bytes` (64-byte lines, 4 ways), rays interleaved `InFlight` at a time:
    * cold, over every ray from an empty cache; warm, over the odd-numbered rays after the even-numbered ones
    * have filled it (other rays of the same kind: a cache kept across batches).
    */
  def cacheRate(traces: IndexedSeq[Array[Long]], bytes: Long, nodeBytes: Int, nodeOffset: Long): (Double, Double) = {
    val line = 64; val ways = 4
    val sets = (bytes / (line * ways)).toInt
    val lru = Array.fill(sets)(mutable.ArrayBuffer.empty[Long])
    var hits, total = 0L
    def access(node: Long): Unit = {
      val first = (nodeOffset + node * nodeBytes) / line
      val last = (nodeOffset + (node + 1) * nodeBytes - 1) / line
      var all = true
      for (l <- first to last) {
        val s = lru((l % sets).toInt)
        val k = s.indexOf(l)
        if (k >= 0) s.remove(k) else { all = false; if (s.size == ways) s.remove(0) }
        s += l
      }
      if (all) hits += 1
      total += 1
    }
    def pass(traces: IndexedSeq[Array[Long]]): Double = {
      hits = 0; total = 0
      for (group <- traces.grouped(InFlight)) {
        val at = Array.fill(group.size)(0)
        var live = true
        while (live) {
          live = false
          for (r <- group.indices if at(r) < group(r).length) { access(group(r)(at(r))); at(r) += 1; live = true }
        }
      }
      hits.toDouble / total
    }
    val cold = pass(traces)
    lru.foreach(_.clear())
    pass(traces.indices.filter(_ % 2 == 0).map(traces))
    (cold, pass(traces.indices.filter(_ % 2 == 1).map(traces)))
  }
}
