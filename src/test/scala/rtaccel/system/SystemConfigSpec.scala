package rtaccel.system

import org.scalatest.flatspec.AnyFlatSpec

/** The settings that make passes to every SystemConfig through the environment (AXI_DATA_BITS, NODE_STORE_KIB):
  * their defaults, the values they take and the error for anything else; and the stores' copies and the ports
  * their clients read on. No hardware.
  */
class SystemConfigSpec extends AnyFlatSpec {
  behavior of "SystemConfig's environment settings"

  it should "take AXI_DATA_BITS as 512 or 1024 and refuse any other width by name" in {
    assert(SystemConfig.axiDataBitsOf(None) == 512 && SystemConfig.axiDataBitsOf(Some(" ")) == 512)
    assert(SystemConfig.axiDataBitsOf(Some("1024")) == 1024)
    val bad = intercept[IllegalArgumentException](SystemConfig.axiDataBitsOf(Some("256")))
    assert(bad.getMessage.contains("AXI_DATA_BITS=256") && bad.getMessage.contains("512, 1024"), bad.getMessage)
  }

  it should "take NODE_STORE_KIB as whole KiB from 0 to the maximum, 1.5 MiB when unset, and refuse anything else" in {
    assert(SystemConfig.nodeStoreBytesOf(None) == 1536 * 1024 && SystemConfig.nodeStoreBytesOf(Some("")) == 1536 * 1024)
    assert(SystemConfig.nodeStoreBytesOf(Some("512")) == 512 * 1024)
    assert(SystemConfig.nodeStoreBytesOf(Some("0")) == 0, "0: no node store")
    assert(SystemConfig.nodeStoreBytesOf(Some(SystemConfig.MaxNodeStoreKib.toString)) == 4096 * 1024)
    for (v <- Seq("-1", "1.5", "4097", "1 MiB", "99999999999")) {
      val bad = intercept[IllegalArgumentException](SystemConfig.nodeStoreBytesOf(Some(v)))
      assert(bad.getMessage.contains(s"NODE_STORE_KIB=$v") && bad.getMessage.contains("4096"), bad.getMessage)
    }
    // Every layout's node word divides a whole KiB, so any setting builds (NodeStore's own requirement).
    assert(SystemConfig(nodeStoreBytes = SystemConfig.nodeStoreBytesOf(Some("1"))).nodeStoreBytes == 1024)
  }

  it should "build one copy of each store by default and refuse more copies than one per two cores by name" in {
    assert(SystemConfig(cores = 4).storeCopies == 1 && SystemConfig(cores = 4).storeCopiesFor(4) == 1)
    assert(SystemConfig(cores = 4, storeCopies = 2).storeCopiesFor(4) == 2)
    // Two clients per copy or fewer: a port each; more: a copy's clients share both its ports.
    assert(StorePort.assign(4, 1) == Seq(StorePort.Group(0, Seq(0, 1), Seq(0, 1, 2, 3))))
    assert(StorePort.assign(3, 2) == Seq(0, 1, 2).map(c => StorePort.Group(c / 2, Seq(c % 2), Seq(c))))
    assert(
      StorePort.assign(5, 2) == Seq(
        StorePort.Group(0, Seq(0, 1), Seq(0, 2, 4)),
        StorePort.Group(1, Seq(0, 1), Seq(1, 3))
      )
    )
    val bad = intercept[IllegalArgumentException](SystemConfig(cores = 3, storeCopies = 3))
    assert(bad.getMessage.contains("storeCopies") && bad.getMessage.contains("got 3"), bad.getMessage)
  }
}
