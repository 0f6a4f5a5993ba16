package rtaccel.regress

import java.io.PrintStream

/** A progress line for long simulations (make regress, CppSimCompare): rays
  * answered of the total, percent, elapsed time and ETA. The Scala
  * twin of sw/include/rtaccel_progress.hpp (same rules, same line):
  *  - nothing for the first 3 s (short runs stay quiet);
  *  - a terminal: one line redrawn in place with \r at most 4 times a second,
  *    ended by `finish`;
  *  - otherwise (sbt's forked JVM, CI logs): a plain line on stdout at most
  *    every 10 s, and a last one from `finish` if any was printed.
  * RTACCEL_PROGRESS=off|plain|tty overrides the choice (sbt pipes a forked
  * JVM's output, so it never looks like a terminal). Only what is printed
  * depends on time; nothing a test checks reads it.
  */
final class Progress(label: String, total: Long, mode: Progress.Mode = Progress.defaultMode) {
  // Plain lines go to stdout: sbt tags every stderr line of a forked JVM "[error]".
  private val to: PrintStream = if (mode == Progress.Tty) System.err else System.out
  import Progress._
  private val start = System.nanoTime()
  private var nextAt = 0.0
  private var width = 0
  private var drawn, finished = false

  private def seconds = (System.nanoTime() - start) / 1e9

  /** Cheap when nothing is due (one clock read). */
  def update(done: Long): Unit = if (mode != Off && !finished) {
    val s = seconds
    if (s >= QuietSeconds && s >= nextAt) {
      draw(done, s)
      nextAt = s + (if (mode == Tty) 0.25 else 10.0)
    }
  }

  /** The last line (if any was drawn); later updates print nothing. */
  def finish(done: Long): Unit = if (!finished) {
    finished = true
    if (drawn) {
      draw(done, seconds)
      if (mode == Tty) to.println()
    }
  }

  private def draw(done: Long, s: Double): Unit = {
    val l = line(label, done, total, s, bar = mode == Tty)
    // \r and a pad over a longer previous line.
    if (mode == Tty) to.print("\r" + l.padTo(width, ' ')) else to.println(l)
    to.flush()
    width = l.length
    drawn = true
  }
}

object Progress {
  sealed trait Mode
  case object Off extends Mode
  case object Plain extends Mode
  case object Tty extends Mode
  val QuietSeconds = 3.0

  def defaultMode: Mode = sys.env.get("RTACCEL_PROGRESS") match {
    case Some("off")   => Off
    case Some("plain") => Plain
    case Some("tty")   => Tty
    case _             => if (System.console() != null) Tty else Plain
  }

  /** "label [#####-----]  45.1%  29,538/65,536 rays  0:12 elapsed, ETA 0:15" (no bar in plain mode). */
  def line(label: String, done: Long, total: Long, seconds: Double, bar: Boolean): String = {
    val d = done.min(total)
    val frac = if (total > 0) d.toDouble / total else 1.0
    val b = if (bar) { val w = 24; val full = (frac * w).toInt; "[" + "#" * full + "-" * (w - full) + "] " }
    else ""
    val eta = if (done > 0) clock(seconds * (total - d) / done) else "?"
    f"$label $b${100 * frac}%5.1f%%  $done%,d/$total%,d rays  ${clock(seconds)} elapsed, ETA $eta"
  }

  private def clock(s: Double): String = {
    val t = math.round(s)
    if (t >= 3600) f"${t / 3600}:${t / 60 % 60}%02d:${t % 60}%02d" else f"${t / 60}:${t % 60}%02d"
  }
}
