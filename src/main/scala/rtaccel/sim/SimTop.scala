package rtaccel.sim

import chisel3._
import chisel3.util._
import rtaccel.{AccelConfig, Datapath, RtAccel}

/** Simulation wrapper for speed: each chiseltest peek or poke costs about as
  * much as a clock step (6-25 us here, more for wide values), so the harness
  * peeks one narrow `flags` word per cycle, the wide request and hit fields
  * only when their valid flag is set, and pokes packed inputs only when they
  * change. Valid because no RtAccel output depends combinationally on an
  * input: the harness can peek, decide, poke, then step.
  */
class SimTop[T <: Data](cfg: AccelConfig, dp: Datapath[T]) extends Module {
  val accel = Module(new RtAccel(cfg, dp))
  private val a0 = accel.io
  private val tagN = accel.io.nodeMem.p.tagBits
  private val tagT = accel.io.triMem.p.tagBits
  val io = IO(new Bundle {

    /** Bit 0 rays.valid, 1 hits.ready, 2 node req.ready, 3 triangle req.ready. */
    val ctrl = Input(UInt(4.W))

    /** The offered ray, packed as SimTop.packRay does. */
    val ray = Input(UInt(SimTop.RayBits.W))
    val nodeBase = Input(UInt(cfg.addrBits.W))
    val triBase = Input(UInt(cfg.addrBits.W))

    /** Bit 0 valid, then the tag, then the record (SimTop.packResp). */
    val nodeResp = Input(UInt((1 + tagN + accel.io.nodeMem.p.dataBits).W))
    val triResp = Input(UInt((1 + tagT + accel.io.triMem.p.dataBits).W))

    /** Handshake bits, peeked every cycle (SimTop.flagFields). */
    val flags = Output(UInt(SimTop.flagFields.size.W))

    /** Wide fields, peeked only when their valid flag is set. */
    val nodeReq = Output(UInt((a0.nodeMem.p.addrBits + tagN).W))
    val triReq = Output(UInt((a0.triMem.p.addrBits + tagT).W))
    val hit = Output(UInt(SimTop.width(cfg, accel).W))
    val perf = Output(chiselTypeOf(accel.io.perf))
  })
  override def desiredName = s"SimTop_${dp.name}_n${cfg.numRayIds}_d${cfg.stackDepth}"

  private val a = accel.io
  private def w32(word: UInt, i: Int): UInt = word(32 * i + 31, 32 * i)
  a.rays.valid := io.ctrl(0)
  a.rays.bits.number := w32(io.ray, 0)
  for (k <- 0 until 3) {
    a.rays.bits.ray.origin(k) := w32(io.ray, 1 + k)
    a.rays.bits.ray.dir(k) := w32(io.ray, 4 + k)
  }
  a.rays.bits.ray.tmin := w32(io.ray, 7)
  a.rays.bits.ray.tmax := w32(io.ray, 8)
  a.rays.bits.shadow := io.ray(9 * 32)
  a.hits.ready := io.ctrl(1)
  a.nodeBase := io.nodeBase
  a.triBase := io.triBase
  a.nodeMem.req.ready := io.ctrl(2)
  a.nodeMem.resp.valid := io.nodeResp(0)
  a.nodeMem.resp.bits.tag := io.nodeResp(tagN, 1)
  a.nodeMem.resp.bits.data := io.nodeResp >> (1 + tagN)
  a.triMem.req.ready := io.ctrl(3)
  a.triMem.resp.valid := io.triResp(0)
  a.triMem.resp.bits.tag := io.triResp(tagT, 1)
  a.triMem.resp.bits.data := io.triResp >> (1 + tagT)
  io.perf := a.perf
  io.flags := Cat(SimTop.flagFields.reverse.map(SimTop.flag(accel, _)))
  io.nodeReq := Cat(a.nodeMem.req.bits.tag, a.nodeMem.req.bits.addr)
  io.triReq := Cat(a.triMem.req.bits.tag, a.triMem.req.bits.addr)
  io.hit := Cat(SimTop.fields(accel).reverse.map(_._2))
}

object SimTop {
  val RayBits: Int = 9 * 32 + 1

  def packRay(r: rtaccel.golden.RayRecord): BigInt = {
    val words = Seq(r.number) ++ r.origin ++ r.dir ++ Seq(r.tmin, r.tmax)
    words.zipWithIndex.map { case (w, i) => BigInt(w & 0xffffffffL) << (32 * i) }.sum + (if (r.shadow)
                                                                                           BigInt(1) << (9 * 32)
                                                                                         else 0)
  }
  def packResp(tagBits: Int, r: Option[(Int, BigInt)]): BigInt =
    r.fold(BigInt(0)) { case (tag, data) => 1 + (BigInt(tag) << 1) + (data << (1 + tagBits)) }

  /** Handshake outputs in `flags`, least significant first. */
  val flagFields: Seq[String] =
    Seq("raysReady", "hitsValid", "broken", "nodeReqValid", "nodeRespReady", "triReqValid", "triRespReady")
  def flag[T <: Data](accel: RtAccel[T], name: String): Bool = {
    val a = accel.io
    name match {
      case "raysReady"    => a.rays.ready; case "hitsValid"            => a.hits.valid; case "broken" => a.broken
      case "nodeReqValid" => a.nodeMem.req.valid; case "nodeRespReady" => a.nodeMem.resp.ready
      case "triReqValid"  => a.triMem.req.valid; case "triRespReady"   => a.triMem.resp.ready
    }
  }

  /** The hit fields packed in `hit`, least significant first. */
  def fields[T <: Data](accel: RtAccel[T]): Seq[(String, UInt)] = {
    val h = accel.io.hits.bits
    Seq(
      "hitNumber" -> h.number,
      "hitHit" -> h.hit.asUInt,
      "hitT" -> h.t,
      "hitU" -> h.u,
      "hitV" -> h.v,
      "hitPrim" -> h.prim,
      "hitErrors" -> h.errors
    )
  }
  def width[T <: Data](cfg: AccelConfig, accel: RtAccel[T]): Int = fields(accel).map(_._2.getWidth).sum

  /** Unpacks a peeked `hit` word by field name. */
  final class Status[T <: Data](accel: RtAccel[T]) {
    private val layout: Map[String, (Int, Int)] = {
      val ws = fields(accel).map { case (n, u) => n -> u.getWidth }
      ws.zip(ws.scanLeft(0)(_ + _._2)).map { case ((n, w), off) => n -> (off, w) }.toMap
    }
    def apply(word: BigInt, name: String): BigInt = {
      val (off, w) = layout(name)
      (word >> off) & ((BigInt(1) << w) - 1)
    }
  }
}
