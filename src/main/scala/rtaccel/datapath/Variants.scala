package rtaccel.datapath

/** Which ray/triangle test a datapath uses (docs/kernels.md sections 4, 5). */
sealed abstract class TriangleTest(val tag: String)
object TriangleTest {

  /** Nori-compatible Moller-Trumbore: bit-exact with Nori in FP32 RNE; leaks on shared edges. */
  case object Moller extends TriangleTest("mt")

  /** Woop-Benthin-Wald shear with the sign-symmetric tie rule: no leaks on a closed mesh. */
  case object Watertight extends TriangleTest("wt")
  val all: Seq[TriangleTest] = Seq(Moller, Watertight)

  /** `make` spelling (TRIANGLE=moller|watertight) or the short tag. */
  def parse(s: String): TriangleTest = s match {
    case "moller" | "mt"     => Moller
    case "watertight" | "wt" => Watertight
    case other               => throw new IllegalArgumentException(s"TRIANGLE=$other: expected moller or watertight")
  }
}

/** How the box test rounds (docs/kernels.md section 3). */
sealed abstract class BoxRounding(val tag: String)
object BoxRounding {

  /** Round to nearest even everywhere: bit-exact with the HLS twin in FP32. */
  case object Nearest extends BoxRounding("rne")

  /** Directed rounding: the computed [near, far] encloses the exact one, so no false misses. */
  case object Conservative extends BoxRounding("cons")
  val all: Seq[BoxRounding] = Seq(Nearest, Conservative)

  /** `make` spelling (ROUNDING=rne|conservative) or the short tag. */
  def parse(s: String): BoxRounding = s match {
    case "rne" | "nearest"       => Nearest
    case "conservative" | "cons" => Conservative
    case other                   => throw new IllegalArgumentException(s"ROUNDING=$other: expected rne or conservative")
  }
}
