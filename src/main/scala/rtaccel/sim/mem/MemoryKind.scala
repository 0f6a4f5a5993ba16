package rtaccel.sim.mem

/** The clock the accelerator runs at, which turns the memory's nanoseconds
  * and bytes per second into cycles.
  *
  * Default 200 MHz: the user-interface clock of a Xilinx MIG driving DDR3-1600
  * in 4:1 mode (800 MHz memory clock / 4). Its application data path is 512
  * bits wide (2 x 4 x 64 DQ), one BL8 burst per cycle, so a core clocked with
  * the controller sees the DRAM's peak as 64 bytes per cycle.
  */
final case class FabricClock(mhz: Double = FabricClock.DefaultMhz) {
  require(mhz > 0 && !mhz.isInfinite, s"fabric clock: '$mhz' MHz is not a positive frequency")

  /** Whole cycles covering `ns` (ceil, in exact decimal arithmetic: 100 ns at 200 MHz is 20 cycles, not 21). */
  def cycles(ns: Int): Int =
    (BigDecimal(ns) * BigDecimal(mhz) / 1000).setScale(0, BigDecimal.RoundingMode.CEILING).toInt.max(1)
  def bytesPerCycle(bytesPerSecond: Double): Double = bytesPerSecond / (mhz * 1e6)
  def describe: String = s"${BigDecimal(mhz).bigDecimal.stripTrailingZeros.toPlainString} MHz"
}
object FabricClock {
  val DefaultMhz = 200.0
}

/** A DDR memory as its datasheet states it. Default: the ZC706's PL-side DDR3
  * SODIMM, 64 bits wide at 1600 MT/s with burst length 8: a burst moves 64
  * bytes and the peak is 12.8 GB/s.
  */
final case class DdrDevice(busBits: Int = 64, megaTransfers: Int = 1600, burstLength: Int = 8) {
  require(busBits % 8 == 0 && busBits > 0 && megaTransfers > 0 && burstLength > 0, s"DdrDevice: bad geometry $this")
  val burstBytes: Int = busBits / 8 * burstLength
  val peakBytesPerSecond: Double = busBits / 8 * megaTransfers * 1e6
}

/** What holds the scene while the accelerator runs (`MEMORY=ddr|onchip`). */
sealed trait MemoryKind {
  def name: String
  def describe: String
}
object MemoryKind {

  /** Off-chip DRAM, one for both ports: node and triangle transfers share its
    * bandwidth, and every access is charged whole bursts.
    */
  final case class Ddr(clock: FabricClock = FabricClock(), device: DdrDevice = DdrDevice()) extends MemoryKind {
    def name = "ddr"
    def bytesPerCycle: Double = clock.bytesPerCycle(device.peakBytesPerSecond)
    def describe: String =
      f"ddr at ${clock.describe}: $bytesPerCycle%.1f B/cycle peak, ${device.burstBytes} B bursts shared by both ports"
  }
  object Ddr {

    /** Assumed read round trip through a MIG, request to data (not measured on
      * a board): DDR3-1600 CL11 is 13.75 ns, a row miss adds tRP + tRCD
      * (2 x 13.75 ns), and the MIG's command queue, PHY and read-data
      * pipeline add some 12-16 user-interface cycles (60-80 ns at 200 MHz).
      * That sums to roughly 90-110 ns; 100 ns is the round figure used.
      */
    val DefaultLatency: LatencyNs = LatencyNs(100, 100)
  }

  /** A scene small enough to sit in block RAM: each port has its own, a
    * record wide, read in `OnChip.LatencyCycles` cycles. One record per cycle
    * per port (the port's own limit), no shared bandwidth, no bursts.
    */
  case object OnChip extends MemoryKind {

    /** BRAM read with its output register, plus the address register: 2 cycles. */
    val LatencyCycles = 2
    def name = "onchip"
    def describe = s"onchip: BRAM per port, $LatencyCycles cycles, one record per cycle"
  }

  def parse(s: String): MemoryKind = s match {
    case "ddr"    => Ddr()
    case "onchip" => OnChip
    case other    => throw new IllegalArgumentException(s"memory '$other': expected ddr or onchip")
  }
}
