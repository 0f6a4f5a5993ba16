package rtaccel.traversal

import chisel3._
import chisel3.util._
import rtaccel.AccelConfig

/** A ray's constants and its current tmax, written when it enters. */
class RayEntry[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val rayId = UInt(cfg.rayIdBits.W)
  val statics = gen.cloneType
  val tmax = UInt(cfg.triFloat.width.W)
}

/** A new tmax for a ray (its best hit so far), written when it leaves a leaf. */
class TmaxUpdate(cfg: AccelConfig) extends Bundle {
  val rayId = UInt(cfg.rayIdBits.W)
  val tmax = UInt(cfg.triFloat.width.W)
}

/** One read port: ask with `en`/`rayId`, get the ray the next cycle. */
class RayBufferRead[T <: Data](cfg: AccelConfig, gen: T) extends Bundle {
  val en = Input(Bool())
  val rayId = Input(UInt(cfg.rayIdBits.W))
  val statics = Output(gen.cloneType)
  val tmax = Output(UInt(cfg.triFloat.width.W))
}

/** Every in-flight ray's data, indexed by ray ID.
  *
  * The constants (origin, direction, reciprocal direction, shear, …: type `T`)
  * are written once, when the ray enters; tmax is written then and again each
  * time the ray leaves a leaf with a closer hit. Those two writers share the
  * tmax memory's one write port through a round-robin arbiter, so neither can
  * starve the other. Reads are synchronous (block RAM), one port per reader.
  */
class RayBuffer[T <: Data](cfg: AccelConfig, gen: T, readers: Int) extends Module {
  require(readers >= 1, s"RayBuffer: needs >= 1 reader, got $readers")
  val io = IO(new Bundle {
    val enter = Flipped(Decoupled(new RayEntry(cfg, gen)))
    val update = Flipped(Decoupled(new TmaxUpdate(cfg)))
    val read = Vec(readers, new RayBufferRead(cfg, gen))
  })
  override def desiredName = s"RayBuffer_n${cfg.numRayIds}_r$readers"

  private val statics = SyncReadMem(cfg.numRayIds, gen.cloneType)
  private val tmaxes = SyncReadMem(cfg.numRayIds, UInt(cfg.triFloat.width.W))

  private val arb = Module(new RRArbiter(new TmaxUpdate(cfg), 2))
  arb.io.in(0).valid := io.enter.valid
  arb.io.in(0).bits.rayId := io.enter.bits.rayId
  arb.io.in(0).bits.tmax := io.enter.bits.tmax
  io.enter.ready := arb.io.in(0).ready
  arb.io.in(1) <> io.update
  arb.io.out.ready := true.B

  when(arb.io.out.valid) { tmaxes.write(arb.io.out.bits.rayId, arb.io.out.bits.tmax) }
  when(io.enter.fire) { statics.write(io.enter.bits.rayId, io.enter.bits.statics) }

  for (r <- io.read) {
    r.statics := statics.read(r.rayId, r.en)
    r.tmax := tmaxes.read(r.rayId, r.en)
  }
}
