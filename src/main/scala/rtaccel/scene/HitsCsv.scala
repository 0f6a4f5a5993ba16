package rtaccel.scene

import rtaccel.golden.HitRecord

import java.nio.file.{Files, Path}

/** `hits.csv` (`ray,hit,t,u,v,prim,error`), the format nori-bridge compare and
  * render read: one line per ray in ray order; a miss has t = inf, u = v = 0,
  * prim = -1.
  */
object HitsCsv {
  val Header = "ray,hit,t,u,v,prim,error"

  def write(path: Path, hits: Seq[HitRecord]): Unit = {
    val sb = new StringBuilder(Header).append('\n')
    for (h <- hits.sortBy(_.number)) {
      if (h.hit) sb.append(
        s"${h.number},1,${FloatText.format(h.t)},${FloatText.format(h.u)},${FloatText.format(h.v)},${h.prim},${h.errors}\n"
      )
      else sb.append(s"${h.number},0,inf,0,0,-1,${h.errors}\n")
    }
    Files.createDirectories(path.toAbsolutePath.getParent)
    Files.writeString(path, sb.toString)
  }
}
