package rtaccel.sim.axi

/** An AR or AW request as the master drives it. */
final case class AxiAddrBeat(id: Int, addr: Long, len: Int, size: Int, burst: Int)
final case class AxiWBeat(data: BigInt, strb: BigInt, last: Boolean)
final case class AxiRBeat(id: Int, data: BigInt, resp: Int, last: Boolean)
final case class AxiBResp(id: Int, resp: Int)

/** The master's outputs in one cycle: a channel's payload is Some when its valid is high. */
final case class AxiMasterSignals(
    ar: Option[AxiAddrBeat],
    aw: Option[AxiAddrBeat],
    w: Option[AxiWBeat],
    rReady: Boolean,
    bReady: Boolean
)

/** The slave's outputs in one cycle: R and B are Some when their valid is high. */
final case class AxiSlaveSignals(
    arReady: Boolean,
    awReady: Boolean,
    wReady: Boolean,
    r: Option[AxiRBeat],
    b: Option[AxiBResp]
)

/** A master broke the AXI4 protocol: the test fails at once, naming the cycle and the rule. */
final class AxiProtocolError(msg: String) extends AssertionError(msg)
