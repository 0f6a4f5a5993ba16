package rtaccel.cocotb

import rtaccel.AccelConfig
import rtaccel.datapath.FloatGolden
import rtaccel.golden.{RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage

import java.nio.file.{Files, Path}

/** The cocotb bench's expected answers: each ray's words and the golden
  * model's hit for it (TraversalGolden, what `make regress` holds the RTL to,
  * bit for bit), one line per ray in ray order (src/test/cocotb/rtaccel_tb/records.py reads it).
  */
object GoldenCsv {
  val Header = "ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow,hit,t,u,v,prim,errors"

  private def hex(w: Long): String = f"0x$w%08x"

  /** Renumbers `rays` 0.. (ray i sits at RAY_BASE + 48 i) and writes them with their golden hits. */
  def write(path: Path, cfg: AccelConfig, image: MemoryImage, golden: FloatGolden, rays: Seq[RayRecord]): Unit = {
    val sb = new StringBuilder(Header).append('\n')
    for ((r0, i) <- rays.zipWithIndex) {
      val r = r0.copy(number = i.toLong)
      val h = TraversalGolden.trace(cfg, image, golden, r).hit
      val words = (r.origin ++ r.dir :+ r.tmin :+ r.tmax).map(hex)
      sb.append((i.toString +: words :+ (if (r.shadow) "1" else "0") :+ (if (h.hit) "1" else "0") :+
        hex(h.t) :+ hex(h.u) :+ hex(h.v) :+ h.prim.toString :+ h.errors.toString).mkString(",")).append('\n')
    }
    Files.createDirectories(path.toAbsolutePath.getParent)
    Files.writeString(path, sb.toString)
  }

  /** Rays the hardware must flag InvalidRay (ErrorFlags doc), each made from a
    * real ray of the scene, interleaved with the real rays unchanged.
    */
  def invalidRays(from: IndexedSeq[RayRecord]): Seq[RayRecord] = {
    val NaN = 0x7fc00000L
    val Inf = 0x7f800000L
    val spoil: Seq[RayRecord => RayRecord] = Seq(
      r => r.copy(origin = r.origin.updated(0, NaN)),
      r => r.copy(dir = r.dir.updated(1, Inf)),
      r => r.copy(dir = r.dir.updated(2, NaN | 0x80000000L)),
      r => r.copy(tmin = NaN),
      r => r.copy(tmax = NaN),
      r => r.copy(dir = Seq(0L, 0L, 0L)),
      r => r.copy(dir = Seq(0x80000000L, 0L, 0x80000000L)),
      r => r.copy(origin = r.origin.updated(2, Inf | 0x80000000L))
    )
    require(from.size >= spoil.size, s"invalidRays: need ${spoil.size} rays to spoil, got ${from.size}")
    spoil.zipWithIndex.flatMap { case (f, i) => Seq(f(from(i)), from(i)) }
  }
}
