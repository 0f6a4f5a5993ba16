package rtaccel.system

import chiseltest._
import org.scalatest.flatspec.AnyFlatSpec
import rtaccel.bvh.BvhLayout
import rtaccel.golden.{RayRecord, TraversalGolden}
import rtaccel.scene.MemoryImage
import rtaccel.sim.axi.AxiMemoryParams
import rtaccel.sim.{Backends, ControlWorkload, FieldDatapath, SystemHarness, SystemSimTop}
import rtaccel.testutil.Seeded
import rtaccel.{AccelConfig, ErrorFlags}

import scala.util.Random

/** Faults at the system top (docs/faults.md), through its ports only, on one
  * DUT in sequence: ABORT at random cycles under back-pressure, a read that
  * never comes (the watchdog), an AXI SLVERR on ray reads and on the scene's
  * store fills, and bursts outside the DMA
  * window; after each, the driver's recovery and a next batch that is exact
  * ray by ray against the golden model.
  */
class SystemFaultsSpec extends AnyFlatSpec with ChiselScalatestTester {
  behavior of "RtAccelSystem under faults"

  private val fieldCfg = AccelConfig(
    numRayIds = 8,
    stackDepth = 12,
    maxNodes = 1 << 10,
    maxTriangles = 1 << 10,
    maxLeafSize = 4,
    layout = BvhLayout.Wide(4)
  )
  private val Unwritten = 0xa5a5a5a5L

  /** Starts a batch of `rays` (hit buffer filled with 0xa5 first); returns at START. */
  private def start[T <: chisel3.Data](
      h: SystemHarness[T],
      rays: IndexedSeq[RayRecord],
      lay: SystemHarness.Layout
  ): Unit = {
    h.putRays(lay.rayBase, rays)
    h.mem.write(lay.hitBase, Array.fill(SystemConfig.HitBytes * rays.size)(0xa5.toByte))
    h.write("RAY_BASE", lay.rayBase); h.write("RAY_COUNT", rays.size); h.write("HIT_BASE", lay.hitBase)
    h.write("IRQ_ENABLE", 7)
    h.command("START")
  }

  /** Waits for the batch's interrupt and clears it; returns IRQ_STATUS. */
  private def end[T <: chisel3.Data](h: SystemHarness[T], limit: Long): Long = {
    h.awaitInterrupt(limit)
    val irq = h.read("IRQ_STATUS")
    assert((irq & 1) == 1, s"interrupt without IRQ_STATUS.DONE ($irq)")
    h.write("IRQ_STATUS", irq)
    assert(!h.status("BUSY"), "BUSY after the batch's interrupt")
    irq
  }

  /** Every written hit record is the golden one; returns how many were written (unwritten ones keep 0xa5). */
  private def written[T <: chisel3.Data](
      h: SystemHarness[T],
      cfg: AccelConfig,
      img: MemoryImage,
      rays: IndexedSeq[RayRecord],
      lay: SystemHarness.Layout,
      what: String
  ): Int = rays.indices.count { i =>
    val (hw, reserved) = h.hitRecord(lay.hitBase, i)
    if (hw.number == Unwritten) false
    else {
      val e = TraversalGolden.trace(cfg, img, FieldDatapath.Golden, rays(i)).hit
      assert(hw.number == i && reserved == 0, s"$what: hit record $i: number ${hw.number}")
      assert(
        TraversalGolden.agrees(rays(i), hw, e),
        s"$what: ray $i: hardware $hw, golden $e (errors ${ErrorFlags.describe(hw.errors)})"
      )
      true
    }
  }

  /** A full batch after a fault: every ray exact, DONE, no fault bit. */
  private def exactBatch[T <: chisel3.Data](
      h: SystemHarness[T],
      cfg: AccelConfig,
      img: MemoryImage,
      rays: IndexedSeq[RayRecord],
      lay: SystemHarness.Layout,
      what: String
  ): Unit = {
    start(h, rays, lay)
    end(h, 2000000)
    assert(
      h.status("DONE") && !h.status("ABORTED") && !h.status("TIMEOUT"),
      s"$what: STATUS ${h.read("STATUS").toHexString}"
    )
    assert(
      written(h, cfg, img, rays, lay, what) == rays.size && h.read("RAYS_DONE") == rays.size,
      s"$what: not every hit written"
    )
    assert(h.read("RAYS_ISSUED") == rays.size, s"$what: RAYS_ISSUED")
  }

  private def recover[T <: chisel3.Data](h: SystemHarness[T], lay: SystemHarness.Layout, what: String): Unit = {
    h.command("SOFT_RESET")
    val s = h.read("STATUS")
    assert(s == 0, s"$what: STATUS after SOFT_RESET is 0x${s.toHexString}, expected 0 (no fault, no scene)")
    assert(h.loadScene(lay.sceneBase) == 0 && h.status("SCENE_READY"), s"$what: scene reload after SOFT_RESET")
  }

  it should "end batches cleanly on ABORT, a lost read, SLVERR and window refusals, and run the next batch exactly" in
    Seeded("SystemFaults.all") { rnd =>
      val (img, _) = ControlWorkload.treeOf(BvhLayout.Wide(4), rnd)
      val cfg = fieldCfg.copy(stackDepth = img.bvhDepth.toInt.max(1))
      // One core and 96 rays: the smallest system that has rays in flight at an ABORT (make test's cost).
      val sys = SystemConfig(core = cfg, cores = 1)
      val rays = ControlWorkload.makeRays(rnd, 96).zipWithIndex.map { case (r, i) => r.copy(number = i.toLong) }
      val lay = SystemHarness.layout(img, rays.size, skew = 3)
      val rayEnd = lay.rayBase + SystemConfig.RayBytes * rays.size
      def inRays(a: Long) = a >= lay.rayBase && a < rayEnd
      var lose = false
      var slverr = false
      var sceneErr = false // SLVERR on the store fills' reads: the image past its header
      def inFills(a: Long) = a >= lay.sceneBase + 64 && a < lay.sceneBase + img.bytes.length
      val params = AxiMemoryParams().harsh(rnd.nextLong())
        .copy(lostAt = a => lose && inRays(a), errorAt = a => (slverr && inRays(a)) || (sceneErr && inFills(a)))
      test(new SystemSimTop(sys, FieldDatapath)).withAnnotations(Backends.verilator) { dut =>
        val h = new SystemHarness(dut, params)
        h.put(lay.sceneBase, img.bytes)
        assert(h.read("WATCHDOG_CYCLES") == RegisterMap.WatchdogDefault && h.read("VERSION") == RegisterMap.Version)
        assert(h.loadScene(lay.sceneBase) == 0)
        h.command("ABORT") // without a batch: ignored
        assert(h.read("STATUS") == 0x4, "ABORT without a batch changes nothing")

        // ---- ABORT at random cycles under back-pressure, within a whole batch's length ----
        val t0 = h.cycle
        exactBatch(h, cfg, img, rays, lay, "before any fault")
        val batchCycles = (h.cycle - t0).toInt
        var aborted = 0
        for (trial <- 0 until 4) {
          start(h, rays, lay)
          val at = rnd.nextInt(batchCycles)
          for (_ <- 0 until at) h.step()
          h.command("ABORT")
          end(h, 2000000)
          val (done, issued) = (h.read("RAYS_DONE"), h.read("RAYS_ISSUED"))
          val what = s"ABORT $trial at cycle $at"
          assert(h.status("ABORTED") != h.status("DONE"), s"$what: exactly one of ABORTED and DONE")
          if (h.status("ABORTED")) aborted += 1
          assert(done == issued && issued <= rays.size, s"$what: RAYS_DONE $done, RAYS_ISSUED $issued")
          assert(
            written(h, cfg, img, rays, lay, what) == done,
            s"$what: hit records written differ from RAYS_DONE $done"
          )
          assert(!h.status("BROKEN") && !h.status("AXI_ERROR"), s"$what: fault bits")
          println(s"$what: ${if (h.status("ABORTED")) "ABORTED" else "DONE"} after $issued of ${rays.size} rays")
        }
        assert(aborted >= 1, "no trial ABORTed a running batch: the abort cycles are too late for this batch")
        exactBatch(h, cfg, img, rays, lay, "after ABORT")

        // ---- a read that never comes: the watchdog ends the batch ----
        val limit = 3000
        h.write("WATCHDOG_CYCLES", limit)
        lose = true
        val t1 = h.cycle
        start(h, rays, lay)
        val irq = end(h, 10 * limit)
        val took = h.cycle - t1
        assert(
          (irq & 4) == 4 && h.status("TIMEOUT") && !h.status("DONE"),
          s"lost read: IRQ $irq, STATUS ${h.read("STATUS").toHexString}"
        )
        assert(
          took >= limit && took <= limit + 200,
          s"lost read: the batch ended $took cycles after START, watchdog $limit"
        )
        assert(h.model.lostBursts > 0, "the memory lost no burst")
        h.command("START")
        for (_ <- 0 until 10) h.step()
        assert(!h.status("BUSY") && h.status("TIMEOUT"), "START while TIMEOUT is ignored")
        lose = false
        recover(h, lay, "after the watchdog")
        assert(h.read("WATCHDOG_CYCLES") == limit, "SOFT_RESET keeps the registers")
        exactBatch(h, cfg, img, rays, lay, "after the watchdog")

        // ---- SLVERR on the ray reads: the batch stops and says AXI_ERROR ----
        slverr = true
        start(h, rays, lay)
        end(h, 2000000)
        assert(
          h.status("AXI_ERROR") && h.status("ABORTED") && h.read("RAYS_DONE") == h.read("RAYS_ISSUED"),
          "SLVERR on ray reads"
        )
        slverr = false
        recover(h, lay, "after SLVERR")
        exactBatch(h, cfg, img, rays, lay, "after SLVERR")

        // ---- SLVERR on the scene's store fills: the load still ends (IRQ SCENE), with AXI_ERROR, not by the watchdog ----
        sceneErr = true
        assert(
          h.loadScene(lay.sceneBase, limit = 20000) == 0 && h.status("AXI_ERROR") && !h.status("TIMEOUT"),
          s"SLVERR on the store fills: STATUS 0x${h.read("STATUS").toHexString}"
        )
        sceneErr = false
        recover(h, lay, "after SLVERR on the store fills")
        exactBatch(h, cfg, img, rays, lay, "after SLVERR on the store fills")

        // ---- the DMA window: the hit buffer outside it ----
        var lo = 0L
        var hi = 1L << 32
        h.onBurst = (read, a) => {
          val end = a.addr + (a.len + 1L) * sys.axiDataBytes
          assert(
            a.addr >= lo && end <= hi,
            f"m_axi ${if (read) "read" else "write"} [0x${a.addr}%x, 0x$end%x) outside the window [0x$lo%x, 0x$hi%x)"
          )
        }
        hi = lay.hitBase & ~63L
        h.write("WINDOW_LIMIT", hi)
        start(h, rays, lay)
        end(h, 2000000)
        val refused = h.read("WINDOW_REFUSED")
        val faultAddr = h.read("WINDOW_FAULT_ADDR")
        assert(
          h.status("WINDOW_ERROR") && h.status("ABORTED") && !h.status("AXI_ERROR"),
          s"window: STATUS ${h.read("STATUS").toHexString}"
        )
        assert(
          refused >= 1 && faultAddr >= hi && faultAddr < lay.hitBase + SystemConfig.HitBytes * rays.size,
          s"window: $refused refused, first at $faultAddr"
        )
        assert(written(h, cfg, img, rays, lay, "window") == 0, "a hit record was written outside the window")
        assert(h.read("RAYS_DONE") == h.read("RAYS_ISSUED"), "window: every ray handed out answered")
        println(
          s"window: $refused bursts refused, first at 0x${faultAddr.toHexString}, ${h.read("RAYS_ISSUED")} rays issued"
        )
        // Lock a window that holds the batch: SOFT_RESET keeps it, writes are refused.
        recover(h, lay, "after the window refusal")
        lo = lay.sceneBase; hi = (lay.hitBase + SystemConfig.HitBytes * rays.size + 63) & ~63L
        h.write("WINDOW_BASE", lo); h.write("WINDOW_LIMIT", hi); h.write("WINDOW_LOCK", 1)
        for (r <- Seq("WINDOW_BASE", "WINDOW_LIMIT", "WINDOW_LOCK"))
          assert(h.write(RegisterMap(r).offset, 0) == 2, s"a write to $r while locked: SLVERR")
        h.command("SOFT_RESET")
        assert(
          h.read("WINDOW_BASE") == lo && h.read("WINDOW_LIMIT") == hi && h.read("WINDOW_LOCK") == 1,
          "SOFT_RESET keeps the locked window"
        )
        assert(h.loadScene(lay.sceneBase) == 0)
        exactBatch(h, cfg, img, rays, lay, "in the locked window")
        // A scene outside the locked window: its header read is refused, so the header is not the image's.
        assert(h.loadScene(lay.sceneBase - 4096) == 1 && h.status("WINDOW_ERROR"), "a scene outside the window")
      }
    }
}
