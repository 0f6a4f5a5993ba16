package rtaccel.system

import chisel3.util.log2Ceil
import rtaccel.AccelConfig
import rtaccel.axi.Axi4Params

/** The ZC706 system's one configuration (the system contract, issue 12):
  * everything in `rtaccel.system` derives from it. `cores` copies of the core
  * described by `core`, one AXI4 master to the PL DDR3 (MIG 7-series), one
  * AXI4-Lite slave for the registers (docs/register-map.md).
  *
  * @param core           the accelerator core's configuration, replicated `cores` times
  * @param cores          accelerator cores sharing the memory side
  * @param axiDataBits    m_axi data width: 512, the MIG 7-series user interface of the PL DDR3 (4:1, 64-bit SODIMM)
  * @param axiAddrBits    m_axi address width (the PL DDR3's 1 GB needs 30; 32 as the MIG presents it)
  * @param axiIdBits      m_axi ID width; read IDs name outstanding records (MemoryFabric)
  * @param nodeStoreBytes on-chip node store (top of the tree, preloaded): see docs/node-store.md
  * @param raysPerBlock   rays fetched per ray-DMA read: 4 x 48 B = 192 B = 3 whole 64-byte lines,
  *                       so every block of a 64-aligned RAY_BASE starts on a line
  * @param rayBlockTags   ray-DMA reads in flight (each holds one block buffer, so the buffers never overflow)
  * @param hitQueue       hit records waiting for the write port
  */
case class SystemConfig(
    core: AccelConfig = AccelConfig.zc706,
    cores: Int = 2,
    axiDataBits: Int = 512,
    axiAddrBits: Int = 32,
    axiIdBits: Int = 6,
    nodeStoreBytes: Int = 1024 * 1024,
    raysPerBlock: Int = 4,
    rayBlockTags: Int = 4,
    hitQueue: Int = 4
) {
  require(cores >= 1, s"SystemConfig: cores must be >= 1, got $cores")
  require(nodeStoreBytes >= 0, s"SystemConfig: nodeStoreBytes must be >= 0, got $nodeStoreBytes")
  require(core.addrBits == axiAddrBits, s"SystemConfig: core.addrBits (${core.addrBits}) must equal axiAddrBits ($axiAddrBits)")
  require(raysPerBlock * SystemConfig.RayBytes % 64 == 0, s"SystemConfig: a ray block must be whole 64-byte lines, got $raysPerBlock rays")
  require(rayBlockTags >= 1 && hitQueue >= 1, s"SystemConfig: rayBlockTags and hitQueue must be >= 1")
  val axi: Axi4Params = Axi4Params(addrBits = axiAddrBits, dataBits = axiDataBits, idBits = axiIdBits)

  val axiDataBytes: Int = axiDataBits / 8
  val rayBlockBytes: Int = raysPerBlock * SystemConfig.RayBytes
  val rayTagBits: Int = log2Ceil(rayBlockTags).max(1)
}

object SystemConfig {
  /** Ray and hit records in DDR (docs/register-map.md). */
  val RayBytes = 48
  val HitBytes = 32
  val HeaderBytes = 64
}
