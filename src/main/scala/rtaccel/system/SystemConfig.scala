package rtaccel.system

import chisel3.util.log2Ceil
import rtaccel.AccelConfig

/** The one configuration of the ZC706 system top (docs/register-map.md,
  * /work/notes/system-contract.md): `cores` copies of the core described by
  * `core`, one AXI4 master of `axiDataBits` to the PL DDR3 (MIG 7-series),
  * one AXI4-Lite slave for the registers. Everything in rtaccel.system
  * derives its widths and depths from here.
  *
  * @param nodeStoreBytes on-chip node store (BRAM) in front of DDR, filled at LOAD_SCENE
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
    nodeStoreBytes: Int = 256 * 1024,
    raysPerBlock: Int = 4,
    rayBlockTags: Int = 4,
    hitQueue: Int = 4
) {
  require(cores >= 1, s"SystemConfig: cores must be >= 1, got $cores")
  require(axiDataBits == 512, s"SystemConfig: the MIG side is 512 bits wide (64-byte lines), got $axiDataBits")
  require(axiAddrBits >= 12 && axiAddrBits <= 48, s"SystemConfig: axiAddrBits must be in 12..48, got $axiAddrBits")
  require(axiIdBits >= 1, s"SystemConfig: axiIdBits must be >= 1, got $axiIdBits")
  require(core.addrBits == axiAddrBits, s"SystemConfig: core.addrBits (${core.addrBits}) must equal axiAddrBits ($axiAddrBits)")
  require(raysPerBlock * SystemConfig.RayBytes % 64 == 0, s"SystemConfig: a ray block must be whole 64-byte lines, got $raysPerBlock rays")
  require(rayBlockTags >= 1 && hitQueue >= 1, s"SystemConfig: rayBlockTags and hitQueue must be >= 1")

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
