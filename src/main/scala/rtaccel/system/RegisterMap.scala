package rtaccel.system

import rtaccel.ErrorFlags

/** How software may access a register. */
sealed abstract class Access(val name: String, val rdl: String)
object Access {

  /** Read-only: the hardware drives the value; writes are ignored (OKAY). */
  case object Ro extends Access("ro", "sw = r; hw = w;")

  /** Read-write, byte strobes honoured. */
  case object Rw extends Access("rw", "sw = rw; hw = r;")

  /** Write-only pulses: each written 1 acts for one cycle; reads return 0. */
  case object Wo extends Access("wo", "sw = w; hw = r; singlepulse = true;")

  /** Set by hardware, cleared by writing 1. */
  case object W1c extends Access("w1c", "sw = rw; onwrite = woclr; hw = w; hwset = true;")
}

final case class Field(name: String, lsb: Int, width: Int, desc: String) {
  def mask: Long = ((1L << width) - 1) << lsb
}

/** One 32-bit register. `hiOf`: this is the _HI half of a 64-bit counter whose
  * _LO read latches it (reading _LO copies _HI into a shadow that _HI returns).
  */
final case class Reg(
    name: String,
    offset: Int,
    access: Access,
    desc: String,
    fields: Seq[Field] = Nil,
    reset: Option[Long] = None,
    hiOf: Option[String] = None
)

/** The AXI4-Lite register map: the single source of the Chisel register block
  * (AxiLiteRegs), the C header, docs/reports/register-map.md and the SystemRDL export
  * (rtaccel.tools.RegMapGen). Offsets are grouped by 0x100 pages: identity and
  * configuration, control and status, buffer addresses, batch results,
  * 64-bit performance counters.
  */
object RegisterMap {
  val Id = 0x52544143L // "RTAC"
  val Version = 1L
  val SpaceBytes = 4096
  val AddrBits = 12

  /** The 64-bit counters, summed over cores (CYCLES: the system's own, since START). */
  val counters: Seq[(String, String)] = Seq(
    "CYCLES" -> "Cycles from START until DONE (cleared by START; counts while BUSY).",
    "RAYS_IN" -> "Rays accepted by the cores.",
    "HITS_OUT" -> "Hits given out by the cores.",
    "NODE_FETCHES" -> "Node records requested by the cores.",
    "TRI_FETCHES" -> "Triangle records requested by the cores.",
    "BOX_TESTS" -> "Nodes tested by the box units.",
    "CHILD_BOX_TESTS" -> "Used child boxes among the tested nodes.",
    "TRI_TESTS" -> "Triangle tests.",
    "DECISIONS" -> "Traversal decisions.",
    "LEAF_RETURNS" -> "Decisions for rays back from a leaf.",
    "NODE_STORE_HITS" -> "Node reads served by the on-chip node store.",
    "NODE_STORE_MISSES" -> "Node reads that went to DDR.",
    "AXI_READ_BEATS" -> "m_axi R beats accepted.",
    "AXI_WRITE_BEATS" -> "m_axi W beats accepted.",
    "AXI_READ_STALL" -> "Cycles with m_axi arvalid && !arready.",
    "IN_FLIGHT_SUM" -> "Sum over cycles of the rays in flight in all cores (mean = this / cycles)."
  )

  /** Error flag register names, by ErrorFlags bit. */
  val errorFlags: Seq[(Int, String)] = Seq(
    ErrorFlags.StackOverflow -> "STACK_OVERFLOW",
    ErrorFlags.IndexOverflow -> "INDEX_OVERFLOW",
    ErrorFlags.LeafTooBig -> "LEAF_TOO_BIG",
    ErrorFlags.InvalidRay -> "INVALID_RAY",
    ErrorFlags.BadSceneData -> "BAD_SCENE_DATA"
  )
  require(errorFlags.size == ErrorFlags.width, "RegisterMap: one ERR_COUNT register per ErrorFlags bit")

  /** SCENE_ERROR_CODE values. */
  val sceneErrors: Seq[(Int, String, String)] = Seq(
    (0, "NONE", "no error"),
    (1, "BAD_MAGIC", "the header's magic is not RTACCEL\\0"),
    (2, "BAD_VERSION", "the header's version is not 2"),
    (3, "LAYOUT", "the header's layout differs from the hardware's (CONFIG_LAYOUT)"),
    (4, "RECORD_BYTES", "nodeBytes or triBytes differ from the hardware's"),
    (5, "MISALIGNED", "SCENE_BASE, nodeOffset or triOffset is not a multiple of 64"),
    (6, "STACK_BOUND", "the header's bvhDepth exceeds the hardware stack (CONFIG_STACK_DEPTH)")
  )

  val regs: Seq[Reg] = {
    def ro(name: String, off: Int, desc: String, fields: Seq[Field] = Nil) = Reg(name, off, Access.Ro, desc, fields)
    def rw(name: String, off: Int, desc: String) = Reg(name, off, Access.Rw, desc, reset = Some(0))
    val ident = Seq(
      Reg("ID", 0x000, Access.Ro, "Identifies the block: 0x52544143 (\"RTAC\").", reset = Some(Id)),
      Reg("VERSION", 0x004, Access.Ro, "Register map version.", reset = Some(Version)),
      ro("CONFIG_CORES", 0x010, "Number of cores."),
      ro("CONFIG_LAYOUT", 0x014, "BVH node layout the hardware reads: 0 nori, K = 2, 4, 8 wide."),
      ro("CONFIG_RAY_IDS", 0x018, "Rays in flight per core."),
      ro("CONFIG_STACK_DEPTH", 0x01c, "Traversal stack entries per ray."),
      ro(
        "CONFIG_FLOAT",
        0x020,
        "Datapath number format.",
        Seq(Field("MANTISSA", 0, 8, "mantissa bits"), Field("EXPONENT", 8, 8, "exponent bits"))
      ),
      ro("CONFIG_NODE_STORE_BYTES", 0x024, "On-chip node store size in bytes."),
      ro("CONFIG_AXI_DATA_BITS", 0x028, "m_axi data width in bits.")
    )
    val control = Seq(
      Reg(
        "CTRL",
        0x100,
        Access.Wo,
        "Commands; each written 1 is a one-cycle pulse.",
        Seq(
          Field(
            "START",
            0,
            1,
            "start a batch (ignored while BUSY, without SCENE_READY, or with RAY_BASE or HIT_BASE not 64-byte aligned)"
          ),
          Field("LOAD_SCENE", 1, 1, "load the scene at SCENE_BASE (ignored while BUSY)"),
          Field("CLEAR_COUNTERS", 2, 1, "zero the 64-bit counters except CYCLES")
        )
      ),
      ro(
        "STATUS",
        0x104,
        "State of the block.",
        Seq(
          Field("BUSY", 0, 1, "a batch or a scene load is running"),
          Field("DONE", 1, 1, "the last batch finished: every hit written and acknowledged (cleared by START)"),
          Field("SCENE_READY", 2, 1, "a scene is loaded and checked"),
          Field("SCENE_ERROR", 3, 1, "the last LOAD_SCENE failed (SCENE_ERROR_CODE says why)"),
          Field(
            "BROKEN",
            4,
            1,
            "sticky: a ray was lost or duplicated, or a hit came for a ray not in the batch (never expected)"
          ),
          Field("AXI_ERROR", 5, 1, "sticky: m_axi returned a non-OKAY response")
        )
      ),
      Reg(
        "IRQ_ENABLE",
        0x108,
        Access.Rw,
        "Interrupt enables (interrupt = |(IRQ_STATUS & IRQ_ENABLE)).",
        Seq(
          Field("DONE", 0, 1, "batch done"),
          Field("SCENE", 1, 1, "scene loaded or failed")
        ),
        reset = Some(0)
      ),
      Reg(
        "IRQ_STATUS",
        0x10c,
        Access.W1c,
        "Interrupt causes; write 1 to clear.",
        Seq(
          Field("DONE", 0, 1, "batch done"),
          Field("SCENE", 1, 1, "scene loaded or failed")
        ),
        reset = Some(0)
      ),
      ro(
        "SCENE_ERROR_CODE",
        0x110,
        "Why the last LOAD_SCENE failed: " + sceneErrors.map { case (c, n, _) => s"$c $n" }.mkString(", ") + ".",
        Seq(Field("CODE", 0, 3, "error code"))
      )
    )
    val buffers = Seq(
      rw("SCENE_BASE", 0x200, "DDR byte address of image.bin (64-byte aligned)."),
      rw("RAY_BASE", 0x204, "DDR byte address of ray record 0 (64-byte aligned)."),
      rw("RAY_COUNT", 0x208, "Rays in the batch."),
      rw("HIT_BASE", 0x20c, "DDR byte address of hit record 0 (64-byte aligned).")
    )
    val results = ro("RAYS_DONE", 0x300, "Hit records written and acknowledged in this batch.") +:
      errorFlags.map { case (bit, n) =>
        ro(s"ERR_COUNT_$n", 0x310 + 4 * bit, s"Rays of this batch with ErrorFlags bit $bit ($n).")
      }
    val perf = counters.zipWithIndex.flatMap { case ((n, d), i) =>
      Seq(
        ro(s"${n}_LO", 0x400 + 8 * i, s"$d Bits 31..0; reading it latches _HI."),
        Reg(
          s"${n}_HI",
          0x404 + 8 * i,
          Access.Ro,
          s"$d Bits 63..32, as latched by the last read of ${n}_LO.",
          hiOf = Some(s"${n}_LO")
        )
      )
    }
    ident ++ control ++ buffers ++ results ++ perf
  }

  def apply(name: String): Reg =
    regs.find(_.name == name).getOrElse(throw new NoSuchElementException(s"RegisterMap: no register $name"))
  def index(name: String): Int = regs.indexWhere(_.name == name).ensuring(_ >= 0, s"RegisterMap: no register $name")
  def field(reg: String, field: String): Field = apply(reg).fields.find(_.name == field)
    .getOrElse(throw new NoSuchElementException(s"RegisterMap: $reg has no field $field"))

  require(regs.map(_.offset).distinct.size == regs.size, "RegisterMap: two registers share an offset")
  require(regs.map(_.name).distinct.size == regs.size, "RegisterMap: two registers share a name")
  require(
    regs.forall(r => r.offset % 4 == 0 && r.offset < SpaceBytes),
    "RegisterMap: offsets must be word-aligned and in the 4 KB space"
  )
}
