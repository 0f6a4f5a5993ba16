package rtaccel.testutil

import chiseltest.simulator.WriteVcdAnnotation
import firrtl2.AnnotationSeq

import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._

/** Waveforms for failures only: dumping every run's VCD would cost more than
  * the simulation. Runs are deterministic for a seed, so a failing body is run
  * once more with a VCD, and the failure names the file.
  */
object Waves {
  def onFailure[T](annos: AnnotationSeq)(body: AnnotationSeq => T): T =
    try body(annos)
    catch {
      case first: Throwable =>
        val before = System.currentTimeMillis()
        try body(annos :+ WriteVcdAnnotation)
        catch { case _: Throwable => () }
        val vcd = newest(Paths.get("test_run_dir"), before)
        throw new AssertionError(
          s"${first.getMessage}\nwaveform of the failing run: ${vcd.getOrElse("(none written)")}",
          first
        )
    }

  private def newest(dir: Path, since: Long): Option[Path] =
    if (!Files.isDirectory(dir)) None
    else Files.walk(dir).iterator().asScala
      .filter(p => p.toString.endsWith(".vcd") && Files.getLastModifiedTime(p).toMillis >= since)
      .toSeq.sortBy(p => -Files.getLastModifiedTime(p).toMillis).headOption
}
