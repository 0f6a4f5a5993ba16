package rtaccel.sim.mem

/** What one port's memory system did over a run. `dramBytes` counts whole
  * bursts (0 on chip); `portBytes` is what the port delivered to the design.
  */
final case class MemStats(
    name: String,
    cycles: Long,
    recordBytes: Int,
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
  def portBytes: Long = requests * recordBytes
  def meanOutstanding: Double = per(outstandingSum, cycles)
  def meanMshrs: Double = per(mshrSum, cycles)

  /** Share of line lookups that found their line, or merged into a fetch already under way. */
  def hitRate: Double = per(lineHits, lineHits + primaryMisses + mergedMisses)

  def toJson: String =
    s"""{"name":"$name","cycles":$cycles,"recordBytes":$recordBytes,"requests":$requests,"responses":$responses,""" +
      s""""portBytes":$portBytes,"dramBytes":$dramBytes,""" +
      s""""requestHits":$requestHits,"lineHits":$lineHits,"primaryMisses":$primaryMisses,"mergedMisses":$mergedMisses,""" +
      f""""hitRate":$hitRate%.6f,"stallCycles":$stallCycles,"meanOutstanding":$meanOutstanding%.3f,""" +
      f""""maxOutstanding":$maxOutstanding,"meanMshrs":$meanMshrs%.3f}"""
}

/** What the shared DRAM did over a run: bytes moved (whole bursts, both
  * ports) and the share of its peak bandwidth they used.
  */
final case class DramStats(cycles: Long, bytes: Long, bytesPerCycle: Double, burstBytes: Int, busyCycles: Long) {

  /** Bytes moved over what the channel could have moved in the run's cycles. */
  def busyShare: Double = if (cycles == 0) 0.0 else bytes / (bytesPerCycle * cycles)

  def toJson: ujson.Obj = ujson.Obj(
    "bytes" -> bytes.toDouble,
    "bytesPerCycle" -> bytesPerCycle,
    "burstBytes" -> burstBytes,
    "busyShare" -> busyShare,
    "busyCycles" -> busyCycles.toDouble
  )
}
