package rtaccel.tools

import rtaccel.datapath.{BoxRounding, TriangleTest}
import rtaccel.fp.FloatFormat

import java.nio.file.{Files, Path, Paths}

/** `FLOAT=auto`: the box and triangle formats of the configuration the
  * precision sweep found smallest and still safe (no false miss, false hit or
  * wrong primitive, no hard-case failure, no pixel different from FP32 on any
  * image) for a triangle test and box rounding, read from
  * `docs/reports/speed-vs-error.json` (`make speed-vs-error`).
  */
object SweepChoice {
  val defaultJson: Path = Paths.get("docs/reports/speed-vs-error.json")

  def variant(test: TriangleTest, rounding: BoxRounding): String =
    s"${if (rounding == BoxRounding.Conservative) "conservative" else "rne"}/${if (test == TriangleTest.Watertight) "watertight"
      else "moller"}"

  /** (box format, triangle format) of the smallest safe point for the variant. */
  def smallestSafe(json: Path, test: TriangleTest, rounding: BoxRounding): (FloatFormat, FloatFormat) = {
    val (b, t, _) = smallestSafePoint(json, test, rounding)
    (b, t)
  }

  /** Also the node layout the sweep measured that point on ("nori" in sweeps before the layout dimension). */
  def smallestSafePoint(json: Path, test: TriangleTest, rounding: BoxRounding): (FloatFormat, FloatFormat, String) = {
    if (!Files.exists(json))
      throw new IllegalArgumentException(s"$json: missing; FLOAT=auto needs the precision sweep (make speed-vs-error)")
    val js = ujson.read(Files.readString(json))
    val v = variant(test, rounding)
    val name = js.obj.get("smallest_safe").flatMap(_.obj.get(v))
      .getOrElse(throw new IllegalArgumentException(
        s"$json: no smallest_safe entry for $v (rerun make speed-vs-error)"
      ))
    if (name.isNull)
      throw new IllegalArgumentException(s"$json: no format of the sweep is safe for $v; give FLOAT= explicitly")
    val point = js("points").arr.find(_("name").str == name.str)
      .getOrElse(throw new IllegalArgumentException(
        s"$json: smallest_safe names point ${name.str}, which is not among its points"
      ))
    val c = point("config")
    // Points before the box/triangle split name one format for both.
    def f(k: String) = FloatFormat.parse(c.obj.get(k).fold(c("float").str)(_.str))
    (f("box_float"), f("tri_float"), c.obj.get("layout").fold("nori")(_.str))
  }
}
