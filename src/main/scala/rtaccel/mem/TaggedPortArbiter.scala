package rtaccel.mem

import chisel3._
import chisel3.util._

/** Puts `n` clients' requests onto one memory port, round-robin, and routes
  * each response back to the client that asked.
  *
  * The client number is prepended to the tag on the way out and stripped on
  * the way back, so responses may return in any order. The shared port's
  * `resp.ready` is the addressed client's, so a client that is not ready only
  * holds up the response channel, never another client's requests.
  */
class TaggedPortArbiter(client: MemPortParams, n: Int) extends Module {
  require(n >= 2, s"TaggedPortArbiter: needs >= 2 clients, got $n")
  val srcBits: Int = log2Ceil(n)
  val shared: MemPortParams = client.copy(tagBits = client.tagBits + srcBits)

  val io = IO(new Bundle {
    val clients = Vec(n, Flipped(new MemPort(client)))
    val mem = new MemPort(shared)
  })
  override def desiredName = s"TaggedPortArbiter_n${n}_t${client.tagBits}"

  private val arb = Module(new RRArbiter(new MemRequest(shared), n))
  for ((c, i) <- io.clients.zipWithIndex) {
    arb.io.in(i).valid := c.req.valid
    arb.io.in(i).bits.addr := c.req.bits.addr
    arb.io.in(i).bits.tag := Cat(i.U(srcBits.W), c.req.bits.tag)
    c.req.ready := arb.io.in(i).ready
  }
  io.mem.req <> arb.io.out

  private val src = io.mem.resp.bits.tag(shared.tagBits - 1, client.tagBits)
  for ((c, i) <- io.clients.zipWithIndex) {
    c.resp.valid := io.mem.resp.valid && src === i.U
    c.resp.bits.data := io.mem.resp.bits.data
    c.resp.bits.tag := io.mem.resp.bits.tag(client.tagBits - 1, 0)
  }
  io.mem.resp.ready := VecInit(io.clients.map(_.resp.ready))(src)
}
