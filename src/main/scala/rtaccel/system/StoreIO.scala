package rtaccel.system

import chisel3._
import chisel3.util._
import rtaccel.axi.{Axi4Addr, Axi4Params, Axi4R}
import rtaccel.mem.{MemPortParams, MemRequest, MemResponse}

/** The ports of an on-chip store (NodeStore, TriStore): loaded through
  * `load`, filled through `ar`/`r` (R beats with the store's fill ID, always
  * taken), and serving `clients` read clients of `port`'s records.
  */
class StoreIO(p: Axi4Params, port: MemPortParams, clients: Int) extends Bundle {
  val load = new NodeStoreLoad(p.addrBits)

  /** Would a request at this address hit? (combinational, per client) */
  val probe = Input(Vec(clients, UInt(p.addrBits.W)))
  val hit = Output(Vec(clients, Bool()))
  val req = Vec(clients, Flipped(Decoupled(new MemRequest(port))))
  val resp = Vec(clients, Decoupled(new MemResponse(port)))
  val ar = Decoupled(new Axi4Addr(p))
  val r = Flipped(Valid(new Axi4R(p)))
  val error = Output(Bool())
}
