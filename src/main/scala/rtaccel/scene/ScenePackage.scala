package rtaccel.scene

import rtaccel.AccelConfig
import rtaccel.golden.RayRecord

import java.nio.file.{Files, Path}
import scala.jdk.CollectionConverters._

/** What a scene needs of the hardware (`scene.json`, written by nori-bridge). */
final case class SceneNeeds(
    triangles: Long,
    nodes: Long,
    bvhDepth: Int,
    largestLeaf: Int,
    maxPrim: Long,
    /** Largest |coordinate| of the scene's extent, and its shortest triangle edge. */
    extentAbs: Double,
    smallestEdge: Double
)

/** A compiled scene package (docs/memory-format.md): memory image, rays, needs. */
final case class ScenePackage(dir: Path, image: MemoryImage, rays: IndexedSeq[RayRecord], needs: SceneNeeds) {

  /** The magnitudes this scene and its rays put through the kernels. */
  lazy val range: NumericRange = NumericRange(needs.extentAbs, needs.smallestEdge, rays)

  /** `base` cut down to what this scene needs: the image's node layout, stack
    * depth = the layout's stack bound (bvhDepth), index
    * widths from the node and triangle counts, leaf size from the largest leaf,
    * and exponent bits from the numeric range, narrowed or widened (never past 8:
    * the records are FP32, and a scene needing more is refused by `misfits`).
    * An FP32 datapath keeps its 8 bits: FP32 records then enter unconverted, and
    * the rounding converters a narrower exponent needs on every input cost more
    * than the narrower units save (Cornell box: e7m23 measured 60,147 LUT
    * against 52,553 for e8m23). Ray IDs, mantissa and address width stay as in `base`.
    */
  def sized(base: AccelConfig): AccelConfig = {
    // Each unit's format is sized alone, by the same rule.
    def size(f: rtaccel.fp.FloatFormat) =
      rtaccel.fp.FloatFormat(if (f == rtaccel.fp.FloatFormat.FP32) 8 else range.expBits.min(8), f.manBits)
    base.copy(
      layout = image.layout,
      stackDepth = needs.bvhDepth.max(1),
      maxNodes = needs.nodes.toInt.max(1),
      maxTriangles = needs.triangles.toInt.max(1),
      maxLeafSize = needs.largestLeaf.max(1),
      boxFloat = size(base.boxFloat),
      triFloat = size(base.triFloat)
    )
  }

  /** Why `cfg` cannot run this scene, one line per reason; empty if it can. */
  def misfits(cfg: AccelConfig): Seq[String] =
    structuralMisfits(cfg) ++ Seq(cfg.boxFloat, cfg.triFloat).distinct.flatMap(range.misfit)

  /** The misfits of stack, indices, leaf size and addresses (the numeric range apart). */
  def structuralMisfits(cfg: AccelConfig): Seq[String] = Seq(
    (image.layout != cfg.layout) -> s"the image has ${image.layout.name} nodes (${image.nodeBytes} bytes); the hardware reads ${cfg.layout.name} nodes (${cfg.layout.nodeBytes} bytes)",
    (needs.bvhDepth > cfg.stackDepth) -> s"the BVH needs a stack of ${needs.bvhDepth} entries; the hardware has stackDepth = ${cfg.stackDepth}",
    (needs.nodes > cfg.maxNodes) -> s"${needs.nodes} nodes exceed maxNodes = ${cfg.maxNodes} (${cfg.nodeIndexBits}-bit node index)",
    (needs.triangles > cfg.maxTriangles) -> s"${needs.triangles} triangles exceed maxTriangles = ${cfg.maxTriangles} (${cfg.triIndexBits}-bit triangle index)",
    (needs.maxPrim >= (1L << cfg.triIndexBits)) -> s"prim number ${needs.maxPrim} does not fit the ${cfg.triIndexBits}-bit triangle index",
    (needs.largestLeaf > cfg.maxLeafSize) -> s"a leaf holds ${needs.largestLeaf} triangles; the hardware takes at most maxLeafSize = ${cfg.maxLeafSize}",
    (image.bytes.length.toLong > (1L << cfg.addrBits)) -> s"the ${image.bytes.length}-byte image does not fit ${cfg.addrBits}-bit addresses"
  ).collect { case (true, why) => why }
}

object ScenePackage {
  def load(dir: Path): ScenePackage = {
    if (!Files.isDirectory(dir))
      throw new IllegalArgumentException(
        s"$dir: not a scene package directory (make one with `nori-bridge compile <scene.xml> --out $dir`)"
      )
    val image = MemoryImage.load(dir.resolve("image.bin"))
    val rays = readRays(dir.resolve("rays.csv"))
    val needs = readNeeds(dir.resolve("scene.json"), image)
    ScenePackage(dir, image, rays, needs)
  }

  private def need(path: Path): Path = {
    if (!Files.exists(path)) throw new IllegalArgumentException(s"$path: missing (rerun `nori-bridge compile`)")
    path
  }

  private def readNeeds(path: Path, image: MemoryImage): SceneNeeds = {
    val js = ujson.read(Files.readString(need(path)))
    def num(key: String): Long = js.obj.get(key).map(_.num.toLong)
      .getOrElse(throw new IllegalArgumentException(s"$path: no field '$key'"))
    // The largest prim number bounds the index width; it is the triangle count - 1 by construction.
    def nums(key: String): Seq[Double] = js.obj.get(key).map(_.arr.map(_.num).toSeq)
      .getOrElse(throw new IllegalArgumentException(s"$path: no field '$key'"))
    val extentAbs = (nums("extent_min") ++ nums("extent_max")).map(math.abs).maxOption.getOrElse(0.0)
    // serde writes an infinite smallest_edge (no triangles) as null.
    val smallestEdge = js.obj.get("smallest_edge").flatMap(_.numOpt).getOrElse(Double.PositiveInfinity)
    SceneNeeds(
      num("triangles"),
      num("nodes"),
      num("bvh_depth").toInt,
      num("largest_leaf").toInt,
      num("triangles") - 1,
      extentAbs,
      smallestEdge
    )
  }

  /** Parses `rays.csv` (header `ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow`). */
  def readRays(path: Path): IndexedSeq[RayRecord] = {
    val lines = Files.readAllLines(need(path)).asScala.toIndexedSeq
    val header = "ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow"
    if (lines.isEmpty || lines.head.trim != header)
      throw new IllegalArgumentException(s"$path:1: expected header '$header', got '${lines.headOption.getOrElse("")}'")
    lines.zipWithIndex.drop(1).filter(_._1.trim.nonEmpty).map { case (line, i) =>
      val f = line.split(',').map(_.trim)
      def bad(what: String) = throw new IllegalArgumentException(s"$path:${i + 1}: $what in '$line'")
      if (f.length != 10) bad(s"${f.length} fields, expected 10")
      def float(k: Int): Long = FloatText.parse(f(k)).map(FloatText.bits).getOrElse(bad(s"'${f(k)}' is not a float"))
      val number = f(0).toLongOption.getOrElse(bad(s"ray number '${f(0)}'"))
      val shadow = f(9) match { case "0" => false; case "1" => true; case s => bad(s"shadow flag '$s' (0 or 1)") }
      RayRecord(number, (1 to 3).map(float), (4 to 6).map(float), float(7), float(8), shadow)
    }
  }
}

/** Float text as nori-bridge writes it (Rust `{}`: `inf`, `-inf`, `NaN`, shortest round-trip). */
object FloatText {
  def parse(s: String): Option[Float] = s match {
    case "inf" | "+inf" => Some(Float.PositiveInfinity)
    case "-inf"         => Some(Float.NegativeInfinity)
    case "NaN" | "nan"  => Some(Float.NaN)
    case _              => s.toFloatOption
  }
  def bits(x: Float): Long = java.lang.Float.floatToRawIntBits(x).toLong & 0xffffffffL
  def fromBits(b: Long): Float = java.lang.Float.intBitsToFloat(b.toInt)

  /** Shortest text that reads back to the same float (Java's algorithm), Rust-readable. */
  def format(b: Long): String = {
    val x = fromBits(b)
    if (x.isPosInfinity) "inf" else if (x.isNegInfinity) "-inf" else if (x.isNaN) "NaN" else x.toString
  }
}
