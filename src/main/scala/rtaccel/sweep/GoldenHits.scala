package rtaccel.sweep

import rtaccel.AccelConfig
import rtaccel.golden.{ArithGolden, HitRecord, RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage

import java.util.concurrent.{Callable, Executors}
import scala.jdk.CollectionConverters._

/** Every ray of a run through the golden model of a configuration: the
  * hardware's answers bit for bit (the RTL is checked against it on the
  * speed subset), at a fraction of the simulator's cost per ray.
  */
object GoldenHits {
  final case class Result(hits: IndexedSeq[HitRecord], boxTests: Long, triTests: Long) {
    def perRay(n: Long): Double = n.toDouble / hits.size.max(1)
  }

  def run[S](
      cfg: AccelConfig,
      img: MemoryImage,
      golden: ArithGolden[S],
      rays: IndexedSeq[RayRecord],
      threads: Int
  ): Result = {
    // Contiguous chunks, so each worker's memory traffic stays local.
    val chunks = rays.grouped((rays.size + threads * 8 - 1) / (threads * 8).max(1)).toIndexedSeq
    val pool = Executors.newFixedThreadPool(threads)
    try {
      val tasks = chunks.map(c =>
        (() => c.map(r => TraversalGolden.trace(cfg, img, golden, r))): Callable[IndexedSeq[TraversalGolden.Trace]]
      )
      val traces = pool.invokeAll(tasks.asJava).asScala.toIndexedSeq.flatMap(_.get())
      Result(traces.map(_.hit), traces.map(_.boxTests.toLong).sum, traces.map(_.triTests.toLong).sum)
    } finally pool.shutdown()
  }
}
