package rtaccel.mem

/** What one port's memory system did over a run. */
final case class MemStats(
    name: String,
    cycles: Long,
    requests: Long,
    responses: Long,
    dramBytes: Long,
    requestHits: Long,
    lineHits: Long,
    primaryMisses: Long,
    mergedMisses: Long,
    stallCycles: Long,
    outstandingSum: Long,
    maxOutstanding: Int,
    mshrSum: Long
) {
  private def per(n: Long, d: Long): Double = if (d == 0) 0.0 else n.toDouble / d
  def meanOutstanding: Double = per(outstandingSum, cycles)
  def meanMshrs: Double       = per(mshrSum, cycles)
  /** Share of line lookups that found their line, or merged into a fetch already under way. */
  def hitRate: Double = per(lineHits, lineHits + primaryMisses + mergedMisses)

  def toJson: String =
    s"""{"name":"$name","cycles":$cycles,"requests":$requests,"responses":$responses,"dramBytes":$dramBytes,""" +
      s""""requestHits":$requestHits,"lineHits":$lineHits,"primaryMisses":$primaryMisses,"mergedMisses":$mergedMisses,""" +
      f""""hitRate":$hitRate%.6f,"stallCycles":$stallCycles,"meanOutstanding":$meanOutstanding%.3f,""" +
      f""""maxOutstanding":$maxOutstanding,"meanMshrs":$meanMshrs%.3f}"""
}
