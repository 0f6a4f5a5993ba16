package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.mem.{MemPort, MemPortParams}
import rtaccel.scene.MemoryImage

/** LOAD_SCENE: reads the 64-byte image header at `sceneBase`, checks it against
  * the hardware (docs/memory-format.md; codes in RegisterMap.sceneErrors),
  * derives the node and triangle bases, then has the fabric preload its node
  * store, then its triangle store (one after the other: they share the fill's
  * AXI ID, MemoryFabric), and waits for both before `ready`. `finished` pulses when the load ends
  * either way (IRQ SCENE).
  */
class SceneLoader(sys: SystemConfig) extends Module {
  val io = IO(new Bundle {
    val start = Input(Bool())
    val sceneBase = Input(UInt(sys.axiAddrBits.W))
    val mem = new MemPort(SceneLoader.port(sys))
    val store = Flipped(new NodeStoreLoad(sys))
    val triStore = Flipped(new NodeStoreLoad(sys))
    val busy = Output(Bool())
    val ready = Output(Bool())
    val error = Output(Bool())
    val errorCode = Output(UInt(3.W))
    val finished = Output(Bool())
    val nodeBase = Output(UInt(sys.axiAddrBits.W))
    val triBase = Output(UInt(sys.axiAddrBits.W))

    /** `nodeBase` and `triBase` come from a header that passed the checks (since reset): before that they are 0,
      * an address nothing says is the scene's (SystemCore holds the cores' node reads until then). */
    val basesValid = Output(Bool())
  })
  private val sIdle :: sReq :: sResp :: sCheck :: sWait :: sTriStore :: sTriWait :: Nil = Enum(7)
  private val stateReg = RegInit(sIdle)
  private val readyReg = RegInit(false.B)
  private val errorReg = RegInit(false.B)
  private val codeReg = RegInit(0.U(3.W))
  private val baseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val nodeBaseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val triBaseReg = RegInit(0.U(sys.axiAddrBits.W))
  private val basesValidReg = RegInit(false.B)
  private val bytesReg = RegInit(0.U(32.W))
  private val triBytesReg = RegInit(0.U(32.W))
  private val finished = WireDefault(false.B)

  private def fail(code: UInt): Unit = { errorReg := true.B; codeReg := code; stateReg := sIdle; finished := true.B }

  when(io.start && stateReg === sIdle) {
    readyReg := false.B; errorReg := false.B; codeReg := 0.U; baseReg := io.sceneBase
    when(io.sceneBase(5, 0) =/= 0.U) { fail(5.U) }.otherwise { stateReg := sReq }
  }
  io.mem.req.valid := stateReg === sReq
  io.mem.req.bits.addr := baseReg
  io.mem.req.bits.tag := 0.U
  when(io.mem.req.fire) { stateReg := sResp }

  io.mem.resp.ready := stateReg === sResp
  private val w = VecInit.tabulate(16)(k => io.mem.resp.bits.data(32 * k + 31, 32 * k))
  private val magic = java.nio.ByteBuffer.wrap(MemoryImage.Magic).order(java.nio.ByteOrder.LITTLE_ENDIAN)
  private val (magic0, magic1) = (magic.getInt(0).toLong & 0xffffffffL, magic.getInt(4).toLong & 0xffffffffL)
  private val (triCount, nodeOffset, triOffset, nodeBytes, triBytes, bvhDepth, layout) =
    (w(4), w(5), w(6), w(7), w(8), w(10), w(11))
  // The triangle array's bytes, triCount * TriBytes (a power of two, MemoryImage), saturated at 2^32 - 1 (the store
  // takes at most its capacity anyway).
  private val triArrayBytes = triCount << log2Ceil(MemoryImage.TriBytes)
  // The header's checks, each made as it arrives and registered (codes 1..6 in order), and the values derived from
  // it; the next cycle (sCheck) fails the load on the first failed check, or takes the bases and starts the node
  // store's fill. Decided in the answer's cycle, the compares, their order and the bases' valid flag were one
  // path, 5.24 ns (docs/fmax.md). sCheck also starts the node store's fill, so the check adds no cycle to a load.
  private val failedRegs = Reg(Vec(6, Bool()))
  private val nodeBaseNewReg = Reg(UInt(sys.axiAddrBits.W))
  private val triBaseNewReg = Reg(UInt(sys.axiAddrBits.W))
  when(io.mem.resp.fire) {
    failedRegs := VecInit(
      w(0) =/= magic0.U || w(1) =/= magic1.U,
      w(2) =/= MemoryImage.Version.U,
      layout =/= sys.core.layout.code.U,
      nodeBytes =/= sys.core.layout.nodeBytes.U || triBytes =/= MemoryImage.TriBytes.U,
      nodeOffset(5, 0) =/= 0.U || triOffset(5, 0) =/= 0.U,
      bvhDepth > sys.core.stackDepth.U
    )
    nodeBaseNewReg := baseReg + nodeOffset
    triBaseNewReg := baseReg + triOffset
    // The node array's bytes (nodeCount * nodeBytes, at most triOffset - nodeOffset); read only by a fill, which
    // starts only for a header that passed.
    bytesReg := triOffset - nodeOffset
    triBytesReg := Mux(triArrayBytes(triArrayBytes.getWidth - 1, 32).orR, "hffffffff".U, triArrayBytes(31, 0))
    stateReg := sCheck
  }
  private val passed = !failedRegs.asUInt.orR
  when(stateReg === sCheck) {
    when(passed) {
      nodeBaseReg := nodeBaseNewReg
      triBaseReg := triBaseNewReg
      basesValidReg := true.B
      stateReg := sWait
    }.otherwise(fail(PriorityEncoder(failedRegs.asUInt) + 1.U))
  }
  io.store.start := stateReg === sCheck && passed
  io.store.base := nodeBaseNewReg
  io.store.bytes := bytesReg
  // With no triangle store (triStoreBytes = 0) the load ends with the node store's, as before it existed.
  private val afterNodes = if (sys.triStoreBytes > 0) sTriStore else sIdle
  when(stateReg === sWait && io.store.done) {
    stateReg := afterNodes
    if (sys.triStoreBytes == 0) { readyReg := true.B; finished := true.B }
  }
  io.triStore.start := stateReg === sTriStore
  io.triStore.base := triBaseReg
  io.triStore.bytes := triBytesReg
  when(stateReg === sTriStore) { stateReg := sTriWait }
  when(stateReg === sTriWait && io.triStore.done) { stateReg := sIdle; readyReg := true.B; finished := true.B }

  io.busy := stateReg =/= sIdle
  io.ready := readyReg
  io.error := errorReg
  io.errorCode := codeReg
  io.finished := finished
  io.nodeBase := nodeBaseReg
  io.triBase := triBaseReg
  io.basesValid := basesValidReg
}

object SceneLoader {
  def port(sys: SystemConfig): MemPortParams = MemPortParams(sys.axiAddrBits, 1, SystemConfig.HeaderBytes)
}
