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
  * `lockable`: an rw register that WINDOW_LOCK.LOCK freezes until reset (a
  * write then answers SLVERR and changes nothing).
  */
final case class Reg(
    name: String,
    offset: Int,
    access: Access,
    desc: String,
    fields: Seq[Field] = Nil,
    reset: Option[Long] = None,
    hiOf: Option[String] = None,
    lockable: Boolean = false
)

/** The AXI4-Lite register map: the single source of the Chisel register block
  * (AxiLiteRegs), the C header, docs/reports/register-map.md and the SystemRDL export
  * (rtaccel.tools.RegMapGen). Offsets are grouped by 0x100 pages: identity and
  * configuration, control and status, buffer addresses, batch results,
  * 64-bit performance counters.
  */
object RegisterMap {
  val Id = 0x52544143L // "RTAC"
  val Version = 2L
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

  /** WATCHDOG_CYCLES at reset: 2^24 cycles, 168 ms at 100 MHz, far above any ray's time between two events
    * (docs/faults.md), far below a user's patience. */
  val WatchdogDefault: Long = 1L << 24

  private val irqFields = Seq(
    Field("DONE", 0, 1, "batch ended (STATUS: DONE, ABORTED or TIMEOUT says how)"),
    Field("SCENE", 1, 1, "scene loaded or failed"),
    Field("FAULT", 2, 1, "the watchdog fired (STATUS.TIMEOUT)")
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
            "start a batch (ignored while BUSY, without SCENE_READY, with RAY_BASE or HIT_BASE not 64-byte aligned, or while a fault (BROKEN, AXI_ERROR, TIMEOUT, WINDOW_ERROR) awaits SOFT_RESET)"
          ),
          Field(
            "LOAD_SCENE",
            1,
            1,
            "load the scene at SCENE_BASE (ignored while BUSY or while a fault awaits SOFT_RESET)"
          ),
          Field("CLEAR_COUNTERS", 2, 1, "zero the 64-bit counters except CYCLES"),
          Field(
            "ABORT",
            3,
            1,
            "end the running batch: no more rays are handed out, the rays in flight finish and their hits are written; then STATUS.ABORTED and IRQ DONE (ignored without a batch)"
          ),
          Field(
            "SOFT_RESET",
            4,
            1,
            "reset everything but this register block (the scene must be loaded again); the way out after STATUS.TIMEOUT, AXI_ERROR, WINDOW_ERROR or BROKEN"
          )
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
          Field(
            "AXI_ERROR",
            5,
            1,
            "sticky until SOFT_RESET: m_axi returned a non-OKAY response (the batch stops as by ABORT)"
          ),
          Field(
            "ABORTED",
            6,
            1,
            "the last batch was stopped (ABORT, AXI_ERROR or WINDOW_ERROR) after RAYS_ISSUED of its rays; their hits are written (cleared by START)"
          ),
          Field(
            "TIMEOUT",
            7,
            1,
            "sticky until SOFT_RESET: the watchdog ended a batch or a scene load that made no progress for WATCHDOG_CYCLES cycles"
          ),
          Field(
            "WINDOW_ERROR",
            8,
            1,
            "sticky until SOFT_RESET: an m_axi burst outside [WINDOW_BASE, WINDOW_LIMIT) was refused (the batch stops as by ABORT)"
          )
        )
      ),
      Reg(
        "IRQ_ENABLE",
        0x108,
        Access.Rw,
        "Interrupt enables (interrupt = |(IRQ_STATUS & IRQ_ENABLE)).",
        irqFields,
        reset = Some(0)
      ),
      Reg("IRQ_STATUS", 0x10c, Access.W1c, "Interrupt causes; write 1 to clear.", irqFields, reset = Some(0)),
      ro(
        "SCENE_ERROR_CODE",
        0x110,
        "Why the last LOAD_SCENE failed: " + sceneErrors.map { case (c, n, _) => s"$c $n" }.mkString(", ") + ".",
        Seq(Field("CODE", 0, 3, "error code"))
      ),
      Reg(
        "WATCHDOG_CYCLES",
        0x114,
        Access.Rw,
        "The watchdog: a batch or scene load with no progress (no ray handed out, no hit written, " +
          "no scene beat read) for this many cycles ends with STATUS.TIMEOUT; 0 disables it. Default 2^24 (168 ms at 100 MHz; " +
          "docs/faults.md gives the bound).",
        reset = Some(WatchdogDefault)
      )
    )
    val buffers = Seq(
      rw("SCENE_BASE", 0x200, "DDR byte address of image.bin (64-byte aligned)."),
      rw("RAY_BASE", 0x204, "DDR byte address of ray record 0 (64-byte aligned)."),
      rw("RAY_COUNT", 0x208, "Rays in the batch."),
      rw("HIT_BASE", 0x20c, "DDR byte address of hit record 0 (64-byte aligned).")
    )
    val results = Seq(
      ro("RAYS_DONE", 0x300, "Hit records written and acknowledged in this batch."),
      ro("RAYS_ISSUED", 0x304, "Rays of this batch handed to the cores (RAY_COUNT, or fewer after ABORT).")
    ) ++
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
    val window = Seq(
      Reg(
        "WINDOW_BASE",
        0x600,
        Access.Rw,
        "DMA window start: every m_axi burst lies in [WINDOW_BASE, WINDOW_LIMIT); set by privileged code " +
          "(a multiple of the beat, 64 bytes at 512 bits).",
        reset = Some(0),
        lockable = true
      ),
      Reg(
        "WINDOW_LIMIT",
        0x604,
        Access.Rw,
        "DMA window end (exclusive); 0 stands for 2^32, the whole space (the reset value).",
        reset = Some(0),
        lockable = true
      ),
      Reg(
        "WINDOW_LOCK",
        0x608,
        Access.Rw,
        "Writing LOCK = 1 freezes WINDOW_BASE, WINDOW_LIMIT and this register until aresetn " +
          "(SOFT_RESET does not unlock; a write then answers SLVERR).",
        Seq(Field("LOCK", 0, 1, "the window is locked")),
        reset = Some(0),
        lockable = true
      ),
      ro("WINDOW_REFUSED", 0x60c, "m_axi bursts refused for leaving the window, since reset or SOFT_RESET."),
      ro("WINDOW_FAULT_ADDR", 0x610, "Address of the first refused burst since reset or SOFT_RESET.")
    )
    ident ++ control ++ buffers ++ results ++ perf ++ window
  }

  def apply(name: String): Reg =
    regs.find(_.name == name).getOrElse(throw new NoSuchElementException(s"RegisterMap: no register $name"))
  def index(name: String): Int = regs.indexWhere(_.name == name).ensuring(_ >= 0, s"RegisterMap: no register $name")
  def field(reg: String, field: String): Field = apply(reg).fields.find(_.name == field)
    .getOrElse(throw new NoSuchElementException(s"RegisterMap: $reg has no field $field"))

  require(regs.map(_.offset).distinct.size == regs.size, "RegisterMap: two registers share an offset")
  require(regs.map(_.name).distinct.size == regs.size, "RegisterMap: two registers share a name")
  require(regs.forall(r => !r.lockable || r.access == Access.Rw), "RegisterMap: only rw registers are lockable")
  require(
    regs.forall(r => r.offset % 4 == 0 && r.offset < SpaceBytes),
    "RegisterMap: offsets must be word-aligned and in the 4 KB space"
  )
}
