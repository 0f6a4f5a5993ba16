package rtaccel

import chisel3.util.log2Ceil
import rtaccel.fp.FloatFormat
import rtaccel.bvh.BvhLayout
import rtaccel.traversal.GridParams

/** The one configuration every rtaccel module derives its widths and depths
  * from. Nothing else in the generator retypes a width: ask the config.
  *
  * @param numRayIds   rays in flight at once; each carries an ID in [0, numRayIds)
  * @param stackDepth  per-ray traversal stack entries (>= the image's stack bound, bvhDepth; the
  *                    default 64 holds the ~200k-triangle dragon in every layout: 22 nori, 33 4-wide, 51 8-wide)
  * @param maxNodes    largest node count the node index must address
  * @param maxTriangles largest triangle count the triangle index must address
  * @param maxLeafSize largest triangle count in one leaf
  * @param boxFloat    number format of the box lanes (and of their ray constants and entry distances)
  * @param triFloat    number format of the triangle test (its ray constants, t/u/v and the ray's tmax);
  *                    `FLOAT=` sets both (`withFloat`), `BOX_FLOAT=` / `TRI_FLOAT=` one each
  * @param addrBits    byte-address width of the memory ports (32 on the ZC706)
  * @param layout      node layout of the BVH images it reads (BvhLayout), which sets the box lanes
  * @param boxTest     how child boxes are tested (BoxTest): `fp32` everywhere, or `grid` (quantized
  *                    layouts with FP32 boxes only) in the node's own grid
  */
case class AccelConfig(
    numRayIds: Int = 64,
    stackDepth: Int = 64,
    maxNodes: Int = 1 << 21,
    maxTriangles: Int = 1 << 20,
    maxLeafSize: Int = 16,
    boxFloat: FloatFormat = FloatFormat.FP32,
    triFloat: FloatFormat = FloatFormat.FP32,
    addrBits: Int = 32,
    layout: BvhLayout = BvhLayout.Wide(4),
    boxTest: BoxTest = BoxTest.Fp32
) {
  require(numRayIds >= 2, s"AccelConfig: numRayIds must be >= 2, got $numRayIds")
  require(stackDepth >= 1, s"AccelConfig: stackDepth must be >= 1, got $stackDepth")
  require(maxNodes >= 1, s"AccelConfig: maxNodes must be >= 1, got $maxNodes")
  require(maxTriangles >= 1, s"AccelConfig: maxTriangles must be >= 1, got $maxTriangles")
  require(maxLeafSize >= 1, s"AccelConfig: maxLeafSize must be >= 1, got $maxLeafSize")
  require(addrBits >= 8 && addrBits <= 48, s"AccelConfig: addrBits must be in 8..48, got $addrBits")
  // The grid test reads a quantized node's origin, scale and plane offsets, and its per-node stage
  // bounds the FP32 ray (GridNodeStage): nothing else has a grid, or the ray it needs.
  require(
    boxTest != BoxTest.Grid || layout.quantized,
    s"AccelConfig: boxTest = ${boxTest.name} (BOX_TEST=${boxTest.name}) needs a quantized node layout (4q or 8q), got ${layout.name}"
  )
  require(
    boxTest != BoxTest.Grid || boxFloat == FloatFormat.FP32,
    s"AccelConfig: boxTest = ${boxTest.name} (BOX_TEST=${boxTest.name}) needs FP32 box constants, got boxFloat ${boxFloat.name}"
  )

  /** Both units in one format (the `FLOAT=` shorthand). */
  def withFloat(f: FloatFormat): AccelConfig = copy(boxFloat = f, triFloat = f)

  /** `e8m23`, or `e8m10+e8m23` (box + triangle) when they differ: for reports. */
  def floatName: String = if (boxFloat == triFloat) boxFloat.name else s"${boxFloat.name}+${triFloat.name}"

  /** Width of a ray ID. At least 1 bit so that a 1-entry pool still has a wire. */
  val rayIdBits: Int = log2Ceil(numRayIds).max(1)

  /** Width of a stack pointer, which counts 0..stackDepth inclusive. */
  val stackPtrBits: Int = log2Ceil(stackDepth + 1)
  val nodeIndexBits: Int = log2Ceil(maxNodes).max(1)
  val triIndexBits: Int = log2Ceil(maxTriangles).max(1)

  /** Counts 0..maxLeafSize inclusive. */
  val leafCountBits: Int = log2Ceil(maxLeafSize + 1)

  /** A child reference holds a node index or a first triangle slot. */
  val refIndexBits: Int = nodeIndexBits.max(triIndexBits)

  /** Child boxes tested in the node's grid (BoxTest.Grid). */
  def gridBox: Boolean = boxTest == BoxTest.Grid

  /** Widths of the grid box test (8-bit plane offsets, as the 4q/8q records hold them). */
  def gridParams: GridParams = GridParams()

  /** Width of a child's entry distance as TraversalControl orders it: a float of the box format, or
    * (grid) a signed integer relative to the node.
    */
  def nearBits: Int = if (gridBox) gridParams.width else boxFloat.width

  /** Child boxes tested per node, in parallel. */
  val boxLanes: Int = layout.lanes

  /** RayStack banks: a decision's pushes land in consecutive slots, so with at
    * least as many banks as pushes each bank takes at most one write per cycle.
    * A power of two, so the bank of a slot is its low bits.
    */
  val stackBanks: Int = 1 << log2Ceil(layout.maxPushes)

  /** Stack rows per ray in each bank. */
  val stackRows: Int = (stackDepth + stackBanks - 1) / stackBanks
}

object AccelConfig {

  /** The generic configuration `make verilog`, `make bench` and `make regress` target on the ZC706
    * (xc7z045). 128 ray IDs: with 64 a core's pipelines sit idle between rays on chip (Cornell 0.23 rays
    * per cycle per core against 0.32 with 128, docs/fmax.md), and two 128-ID cores still fit beside the
    * system's units at the same clock estimate (`make verilog`).
    */
  val zc706: AccelConfig = AccelConfig(numRayIds = 128)
}
