package rtaccel

/** How the box lanes test a node's child boxes (`AccelConfig.boxTest`, `BOX_TEST=` in `make verilog`,
  * `make regress` and the bench).
  *
  *  - [[BoxTest.Fp32]]: every child box as FP32 planes, K full box lanes (BboxIntersect); a quantized
  *    node's planes are decoded to FP32 first (QuantNode). Every layout.
  *  - [[BoxTest.Grid]]: a quantized node's children tested in the node's own grid
  *    (GridBboxIntersect: one FP32 stage per node, K narrow integer lanes; docs/kernels.md, "Box tests
  *    in the node's grid"). Layouts 4q and 8q with FP32 box constants only.
  */
sealed trait BoxTest {
  def name: String
}

object BoxTest {
  case object Fp32 extends BoxTest { val name = "fp32" }
  case object Grid extends BoxTest { val name = "grid" }

  val all: Seq[BoxTest] = Seq(Fp32, Grid)

  def parse(s: String): BoxTest = all.find(_.name == s.trim)
    .getOrElse(throw new IllegalArgumentException(
      s"box test '$s': expected one of ${all.map(_.name).mkString(", ")}"
    ))
}
