package rtaccel.system

import chisel3.util.log2Ceil
import rtaccel.AccelConfig
import rtaccel.axi.Axi4Params

/** The ZC706 system's one configuration (the system contract):
  * everything in `rtaccel.system` derives from it. `cores` copies of the core
  * described by `core`, one AXI4 master to the PL DDR3 (MIG 7-series), one
  * AXI4-Lite slave for the registers (docs/reports/register-map.md).
  *
  * @param core           the accelerator core's configuration, replicated `cores` times
  * @param cores          accelerator cores sharing the memory side
  * @param axiDataBits    m_axi data width, by default [[SystemConfig.defaultAxiDataBits]]: 512 bits, the MIG
  *                       7-series user interface of the PL DDR3 (4:1, 64-bit SODIMM), one 64-byte beat per cycle;
  *                       or 1024, one 128-byte beat per cycle, what the PL DDR3's 12.8 GB/s carries at 100 MHz
  *                       (the AXI SmartConnect converts width and clock to the MIG's 512 bits at 200 MHz;
  *                       docs/system-wide.md)
  * @param axiAddrBits    m_axi address width (the PL DDR3's 1 GB needs 30; 32 as the MIG presents it)
  * @param axiIdBits      m_axi ID width; read IDs name outstanding records (MemoryFabric)
  * @param nodeStoreBytes on-chip node store (top of the tree, preloaded), by default
  *                       [[SystemConfig.defaultNodeStoreBytes]]: 1.5 MiB, 342 BRAM36, what the block RAM left by
  *                       2 cores and the triangle store holds with room to spare (docs/node-store.md)
  * @param triStoreBytes  on-chip triangle store (the triangle array's first bytes, preloaded), 0 or a power of two:
  *                       see docs/scene-store.md
  * @param raysPerBlock   rays fetched per ray-DMA read: 4 x 48 B = 192 B = 3 whole 64-byte lines,
  *                       so every block of a 64-aligned RAY_BASE starts on a line
  * @param rayBlockTags   ray-DMA reads in flight (each holds one block buffer, so the buffers never overflow);
  *                       they bound the rays fed per cycle at tags x raysPerBlock / the DDR round trip: 16 x 4
  *                       over about 30 cycles is 2 rays/cycle, what 2 cores can take (one ray each per cycle)
  * @param hitQueue       hit lines (one or two records each) waiting for the write port
  * @param hitPairSlots   HitDma's pair buffer, a power of two: hits waiting for their neighbour to share a 64-byte
  *                       line; a conflict (two waiting pairs p, p + slots k) writes a hit alone in its own line, so
  *                       the hit bytes per ray in docs/reports/performance.md (32 with no conflict) show their cost.
  *                       By default [[SystemConfig.pairSlotsFor]]: enough slots for the pairs of every ray in flight
  * @param storeCopies    block-RAM copies of each on-chip store, 1 up to one per two cores: a copy is dual-ported,
  *                       so with more than two cores per copy the cores share its two ports, each port serving
  *                       whichever core waits (StorePort, one cycle more per read). One copy by default: a second copy of the 1.5 MiB node store and the
  *                       triangle store is 399 BRAM36 more, which no third core leaves room for on the xc7z045
  */
case class SystemConfig(
    core: AccelConfig = AccelConfig.zc706,
    cores: Int = 2,
    axiDataBits: Int = SystemConfig.defaultAxiDataBits,
    axiAddrBits: Int = 32,
    axiIdBits: Int = 6,
    nodeStoreBytes: Int = SystemConfig.defaultNodeStoreBytes,
    triStoreBytes: Int = 256 * 1024,
    raysPerBlock: Int = 4,
    rayBlockTags: Int = 16,
    hitQueue: Int = 4,
    hitPairSlots: Option[Int] = None,
    storeCopies: Int = 1
) {
  require(cores >= 1, s"SystemConfig: cores must be >= 1, got $cores")
  require(
    SystemConfig.AxiDataBitsChoices.contains(axiDataBits),
    s"SystemConfig: axiDataBits must be one of ${SystemConfig.AxiDataBitsChoices.mkString(", ")}, got $axiDataBits"
  )
  require(nodeStoreBytes >= 0, s"SystemConfig: nodeStoreBytes must be >= 0, got $nodeStoreBytes")
  require(
    triStoreBytes == 0 || Integer.bitCount(triStoreBytes) == 1 && triStoreBytes >= 2 * axiDataBits / 8,
    s"SystemConfig: triStoreBytes must be 0 or a power of two of at least two beats, got $triStoreBytes"
  )
  require(
    core.addrBits == axiAddrBits,
    s"SystemConfig: core.addrBits (${core.addrBits}) must equal axiAddrBits ($axiAddrBits)"
  )
  require(
    raysPerBlock * SystemConfig.RayBytes % 64 == 0,
    s"SystemConfig: a ray block must be whole 64-byte lines, got $raysPerBlock rays"
  )
  require(rayBlockTags >= 1 && hitQueue >= 1, s"SystemConfig: rayBlockTags and hitQueue must be >= 1")
  require(
    hitPairSlots.forall(n => n >= 1 && Integer.bitCount(n) == 1),
    s"SystemConfig: hitPairSlots must be a power of two, got ${hitPairSlots.getOrElse(0)}"
  )

  /** HitDma's pair buffer: `hitPairSlots`, else [[SystemConfig.pairSlotsFor]] the cores' ray IDs. */
  val pairSlots: Int = hitPairSlots.getOrElse(SystemConfig.pairSlotsFor(cores * core.numRayIds))
  require(
    storeCopies >= 1 && storeCopies <= (cores + 1) / 2,
    s"SystemConfig: storeCopies must be 1 to ceil(cores / 2) = ${(cores + 1) / 2}, got $storeCopies"
  )

  /** The copies of a store with `clients` clients (one per core): [[storeCopies]], at most one per two clients. */
  def storeCopiesFor(clients: Int): Int = storeCopies.min((clients + 1) / 2).max(1)

  val axi: Axi4Params = Axi4Params(addrBits = axiAddrBits, dataBits = axiDataBits, idBits = axiIdBits)

  val axiDataBytes: Int = axiDataBits / 8
  val rayBlockBytes: Int = raysPerBlock * SystemConfig.RayBytes
  val rayTagBits: Int = log2Ceil(rayBlockTags).max(1)
}

object SystemConfig {

  /** Pair-buffer slots for `inFlight` rays: the least power of two of pairs whose numbers span at least
    * `inFlight` rays (64 slots for one core of 128 IDs, 128 for two, 256 for three or four). The rays in flight
    * are about `inFlight` consecutive numbers (RayDma hands them out in order), so while the slowest ray of the
    * window is no older than that, two waiting pairs never share a slot; only a straggler further behind can
    * conflict, and a conflict costs a line, not a record. LUTRAM: a slot holds a 192-bit record and a line
    * address (HitDma).
    */
  def pairSlotsFor(inFlight: Int): Int = {
    require(inFlight >= 2, s"SystemConfig.pairSlotsFor: need at least 2 rays in flight, got $inFlight")
    (1 << log2Ceil(inFlight)) / 2
  }

  /** m_axi widths the system is built and tested for: the MIG's user interface (512) and twice it (1024). */
  val AxiDataBitsChoices: Seq[Int] = Seq(512, 1024)

  /** The m_axi width of every SystemConfig that names none: `AXI_DATA_BITS` from the environment (make passes a
    * command-line variable on to sbt, so `make verilog AXI_DATA_BITS=1024`, `make cppsim-test AXI_DATA_BITS=1024`
    * and a spec run under it all build the wide system), else 512. Read once per JVM.
    */
  lazy val defaultAxiDataBits: Int = axiDataBitsOf(sys.env.get("AXI_DATA_BITS"))
  def axiDataBitsOf(setting: Option[String]): Int = setting.map(_.trim).filter(_.nonEmpty) match {
    case None => 512
    case Some(v) => v.toIntOption.filter(AxiDataBitsChoices.contains).getOrElse(throw new IllegalArgumentException(
        s"AXI_DATA_BITS=$v: the m_axi data width must be one of ${AxiDataBitsChoices.mkString(", ")}"
      ))
  }

  /** The node store of every SystemConfig that names none: `NODE_STORE_KIB` from the environment, as
    * `AXI_DATA_BITS` (`make verilog NODE_STORE_KIB=512`, then `make bench` or `make regress SIM=cpp` with the same
    * setting, sizes the store to a scene or to more cores; `make bench` refuses a resources.md made with another
    * size), else 1.5 MiB. Whole KiB, so that it is a multiple of every layout's node word. Read once per JVM.
    */
  lazy val defaultNodeStoreBytes: Int = nodeStoreBytesOf(sys.env.get("NODE_STORE_KIB"))
  val DefaultNodeStoreKib = 1536

  /** The largest store the setting takes: 4 MiB, past the xc7z045's block RAM (545 BRAM36, about 2.4 MiB). */
  val MaxNodeStoreKib = 4096
  def nodeStoreBytesOf(setting: Option[String]): Int = setting.map(_.trim).filter(_.nonEmpty) match {
    case None => DefaultNodeStoreKib * 1024
    case Some(v) =>
      v.toIntOption.filter(k => k >= 0 && k <= MaxNodeStoreKib).map(_ * 1024).getOrElse(
        throw new IllegalArgumentException(
          s"NODE_STORE_KIB=$v: the node store must be a whole number of KiB from 0 (no store) to $MaxNodeStoreKib"
        )
      )
  }

  /** Ray and hit records in DDR (docs/reports/register-map.md). */
  val RayBytes = 48
  val HitBytes = 32
  val HeaderBytes = 64
}
