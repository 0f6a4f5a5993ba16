package rtaccel.system

import rtaccel.AccelConfig
import rtaccel.axi.Axi4Params

/** The ZC706 system's one configuration (docs/system-contract: issue 12):
  * everything in `rtaccel.system` derives from it.
  *
  * @param core           the accelerator core's configuration, replicated `cores` times
  * @param cores          accelerator cores sharing the memory side
  * @param axiDataBits    m_axi data width: 512, the MIG 7-series user interface of the PL DDR3 (4:1, 64-bit SODIMM)
  * @param axiAddrBits    m_axi address width (the PL DDR3's 1 GB needs 30; 32 as the MIG presents it)
  * @param axiIdBits      m_axi ID width; read IDs name outstanding records (MemoryFabric)
  * @param nodeStoreBytes on-chip node store (top of the tree, preloaded): see docs/node-store.md
  */
case class SystemConfig(
    core: AccelConfig = AccelConfig.zc706,
    cores: Int = 2,
    axiDataBits: Int = 512,
    axiAddrBits: Int = 32,
    axiIdBits: Int = 6,
    nodeStoreBytes: Int = 1024 * 1024
) {
  require(cores >= 1, s"SystemConfig: cores must be >= 1, got $cores")
  require(nodeStoreBytes >= 0, s"SystemConfig: nodeStoreBytes must be >= 0, got $nodeStoreBytes")
  val axi: Axi4Params = Axi4Params(addrBits = axiAddrBits, dataBits = axiDataBits, idBits = axiIdBits)
}
