"""rtaccel_system against independent AXI models.

cocotbext-axi's AxiRam (reads reordered across IDs and delayed, see
rtaccel_tb/ddr.py) on m_axi and its AxiLiteMaster on s_axi, random
back-pressure on every channel of both, our protocol assertions on every
channel (rtaccel_tb/protocol.py), and the driver's register sequence. Every
ray's hit is compared field by field with the golden model's.
"""

import os
import struct

import cocotb
from cocotb.triggers import ClockCycles

from rtaccel_tb.bench import Bench, HIT_BASE, RAY_BASE, SCENE_BASE
from rtaccel_tb.records import RAY_BYTES, HIT_BYTES, Hit, agrees, load_golden


def _image(bench, name="primary"):
    with open(bench.cfg["packages"][name]["image"], "rb") as f:
        return f.read()


def _golden(bench, name):
    return load_golden(bench.cfg["golden"][name])


async def _check_config(bench):
    """ID, VERSION and the CONFIG_* registers describe the generated hardware."""
    c = bench.cfg
    want = {"ID": 0x52544143, "VERSION": c["version"], "CONFIG_CORES": c["cores"], "CONFIG_LAYOUT": c["layout"],
            "CONFIG_RAY_IDS": c["ray_ids"], "CONFIG_STACK_DEPTH": c["stack_depth"],
            "CONFIG_FLOAT": c["float_exp"] << 8 | c["float_man"], "CONFIG_NODE_STORE_BYTES": c["node_store_bytes"],
            "CONFIG_AXI_DATA_BITS": 512}
    got = {k: await bench.read(k) for k in want}
    assert got == want, f"configuration registers: got {got}, want {want}"
    header = c["header"]
    assert os.path.exists(header), f"{header}: missing (regenerate with `make regmap`)"
    bad = bench.regs.header_disagreements(header)
    assert not bad, "the C header disagrees with the register map:\n  " + "\n  ".join(bad[:10])
    bench.log.info("%s agrees with the register map", header)


def _compare(bench, rays, want, blob, what):
    """Every hit record against its golden hit; none lost, none duplicated."""
    ebits = bench.cfg["error_bits"]
    bad, seen = [], set()
    for i, ray in enumerate(rays):
        got, junk = Hit.unpack(blob[HIT_BYTES * i:HIT_BYTES * (i + 1)], ebits)
        if got.number in seen:
            bad.append(f"ray {i}: record holds number {got.number}, a duplicate")
        seen.add(got.number)
        if got.number != i:
            bad.append(f"ray {i}: record number {got.number} (the record of ray {i} is missing or misplaced)")
        elif not agrees(ray, got, want[i]):
            bad.append(f"ray {i}: hardware {got}, golden {want[i]}")
        bad += [f"ray {i}: {j}" for j in junk]
    if bad:
        raise AssertionError(f"{what}: {len(bad)} of {len(rays)} hits wrong, first ones:\n  " + "\n  ".join(bad[:12]))
    bench.log.info("%s: %d rays, every hit equal to the golden model's", what, len(rays))


async def _check_batch(bench, rays, want, blob, cycles, what, ar_before):
    """Results and counters of the batch that just finished (counters cleared before its START)."""
    _compare(bench, rays, want, blob, what)
    st = await bench.status()
    assert st["DONE"] and not st["BUSY"] and st["SCENE_READY"], f"{what}: STATUS after the batch {st}"
    assert not st["BROKEN"] and not st["AXI_ERROR"], f"{what}: STATUS {st}"
    n = len(rays)
    assert await bench.read("RAYS_DONE") == n, f"{what}: RAYS_DONE {await bench.read('RAYS_DONE')}, {n} rays"
    for bit, name in enumerate(bench.cfg["error_names"]):
        expect = sum(1 for h in want if h.errors >> bit & 1)
        got = await bench.read(f"ERR_COUNT_{name}")
        assert got == expect, f"{what}: ERR_COUNT_{name} = {got}, golden says {expect}"
    c = {k: await bench.read64(k) for k in ("CYCLES", "RAYS_IN", "HITS_OUT", "NODE_FETCHES", "NODE_STORE_HITS",
                                            "NODE_STORE_MISSES", "AXI_READ_BEATS", "AXI_WRITE_BEATS", "AXI_READ_STALL",
                                            "IN_FLIGHT_SUM", "TRI_FETCHES", "DECISIONS")}
    bench.log.info("%s: counters %s", what, c)
    assert c["RAYS_IN"] == n and c["HITS_OUT"] == n, f"{what}: RAYS_IN {c['RAYS_IN']}, HITS_OUT {c['HITS_OUT']}, {n} rays"
    assert 0 < c["CYCLES"] <= cycles + 64, f"{what}: CYCLES {c['CYCLES']}, but the interrupt came {cycles} cycles after START"
    assert c["NODE_STORE_HITS"] + c["NODE_STORE_MISSES"] == c["NODE_FETCHES"], f"{what}: node store hits + misses != NODE_FETCHES: {c}"
    axi = bench.monitor.axi
    # The monitor saw every beat since CLEAR_COUNTERS (the system was idle then and is idle now).
    r_beats = axi.channels["r"].beats - ar_before["r"]
    w_beats = axi.channels["w"].beats - ar_before["w"]
    stalls = axi.channels["ar"].stall_cycles - ar_before["ar_stall"]
    assert c["AXI_READ_BEATS"] == r_beats, f"{what}: AXI_READ_BEATS {c['AXI_READ_BEATS']}, the monitor counted {r_beats}"
    assert c["AXI_WRITE_BEATS"] == w_beats, f"{what}: AXI_WRITE_BEATS {c['AXI_WRITE_BEATS']}, the monitor counted {w_beats}"
    assert c["AXI_READ_STALL"] == stalls, f"{what}: AXI_READ_STALL {c['AXI_READ_STALL']}, the monitor counted {stalls}"
    assert w_beats >= (HIT_BYTES * n + 63) // 64, f"{what}: {w_beats} W beats cannot carry {n} hit records"
    # HitDma writes neighbouring hits as one line where it can, else alone: never more lines than records.
    assert w_beats <= n, f"{what}: {w_beats} W beats for {n} hit records (a record written twice, or a line without one)"
    bench.log.info("%s: %d hit records in %d lines", what, n, w_beats)
    assert c["IN_FLIGHT_SUM"] <= c["CYCLES"] * bench.cfg["cores"] * bench.cfg["ray_ids"], f"{what}: IN_FLIGHT_SUM {c}"
    assert axi.outstanding() == 0, f"{what}: AXI transactions still open after DONE"
    bench.monitor.check()


def _snapshot(bench):
    a = bench.monitor.axi.channels
    return {"r": a["r"].beats, "w": a["w"].beats, "ar_stall": a["ar"].stall_cycles}


async def _batch(bench, name, rays, want):
    await bench.write("CTRL", bench.bit("CTRL", "CLEAR_COUNTERS"))
    await ClockCycles(bench.dut.aclk, 2)
    before = _snapshot(bench)
    blob, cycles = await bench.run_batch(rays)
    await _check_batch(bench, rays, want, blob, cycles, name, before)
    bench.log.info("%s: %d rays in %d cycles (%d cores)", name, len(rays), cycles, bench.cfg["cores"])


@cocotb.test()
async def driver_sequence(dut):
    """Load the Cornell box, run its camera rays, then its shadow rays (a second START), hits against the golden model."""
    bench = Bench(dut, "driver_sequence")
    await bench.reset()
    await _check_config(bench)
    st = await bench.status()
    assert not st["SCENE_READY"] and not st["BUSY"] and not st["DONE"], f"STATUS out of reset {st}"
    image = _image(bench)
    st, code = await bench.load_scene(image)
    assert st["SCENE_READY"] and not st["SCENE_ERROR"] and code == 0, f"LOAD_SCENE of a good image: STATUS {st}, code {code}"
    for name in ("primary", "shadow"):
        rays, want = _golden(bench, name)
        await _batch(bench, name, rays, want)
    keep = [(SCENE_BASE, len(image)), (RAY_BASE, RAY_BYTES * len(rays)), (HIT_BASE, HIT_BYTES * len(rays))]
    assert bench.ddr.read(SCENE_BASE, len(image)) == image, "the scene image in DDR changed"
    stray = bench.untouched(keep)
    assert not stray, f"bytes outside the hit buffer were written, first at {stray[:5]}"
    bench.monitor.check()


@cocotb.test()
async def invalid_rays(dut):
    """NaN / infinite / zero-direction rays come back with InvalidRay, the valid ones between them exact."""
    bench = Bench(dut, "invalid_rays")
    await bench.reset()
    st, code = await bench.load_scene(_image(bench))
    assert st["SCENE_READY"] and code == 0, f"LOAD_SCENE: STATUS {st}, code {code}"
    rays, want = _golden(bench, "invalid")
    invalid = 1 << bench.cfg["error_names"].index("INVALID_RAY")
    spoiled = [i for i in range(0, len(rays), 2)]
    assert all(want[i].errors & invalid and not want[i].hit for i in spoiled), "the golden model does not flag the spoiled rays"
    await _batch(bench, "invalid", rays, want)


def _corrupt(image, offset, value):
    b = bytearray(image)
    struct.pack_into("<I", b, offset, value)
    return bytes(b)


@cocotb.test()
async def scene_errors(dut):
    """Each header fault gives SCENE_ERROR with its code; START is then ignored; a good load recovers."""
    bench = Bench(dut, "scene_errors")
    await bench.reset()
    good = _image(bench)
    cfg = bench.cfg
    codes = {name: code for code, name in cfg["scene_errors"]}
    other_layout = 2 if cfg["layout"] != 2 else 4
    cases = [
        ("bad magic", _corrupt(good, 0, 0x41544352), SCENE_BASE, codes["BAD_MAGIC"]),
        ("bad version", _corrupt(good, 8, 2), SCENE_BASE, codes["BAD_VERSION"]),
        ("other layout", _corrupt(good, 44, other_layout), SCENE_BASE, codes["LAYOUT"]),
        ("nodeBytes", _corrupt(good, 28, 32 * other_layout), SCENE_BASE, codes["RECORD_BYTES"]),
        ("triBytes", _corrupt(good, 32, 48), SCENE_BASE, codes["RECORD_BYTES"]),
        ("misaligned base", good, SCENE_BASE + 32, codes["MISALIGNED"]),
        ("stack bound", _corrupt(good, 40, cfg["stack_depth"] + 1), SCENE_BASE, codes["STACK_BOUND"]),
    ]
    rays, want = _golden(bench, "primary")
    rays, want = rays[:16], want[:16]
    for what, image, base, code in cases:
        st, got = await bench.load_scene(image, base)
        assert st["SCENE_ERROR"] and not st["SCENE_READY"], f"{what}: STATUS {st}"
        assert got == code, f"{what}: SCENE_ERROR_CODE {got}, expected {code}"
        # START without a loaded scene: ignored, no DONE, no traffic.
        w_before = bench.monitor.axi.channels["w"].beats
        bench.ddr.write(RAY_BASE, b"".join(r.record() for r in rays))
        await bench.write("RAY_BASE", RAY_BASE)
        await bench.write("RAY_COUNT", len(rays))
        await bench.write("HIT_BASE", HIT_BASE)
        await bench.write("CTRL", bench.bit("CTRL", "START"))
        await bench.quiet(2000)
        st = await bench.status()
        assert not st["DONE"] and not st["BUSY"], f"{what}: START after a failed load was not ignored: STATUS {st}"
        assert bench.monitor.axi.channels["w"].beats == w_before, f"{what}: START after a failed load wrote to DDR"
        bench.log.info("%s: SCENE_ERROR_CODE %d, START ignored", what, got)
    st, code = await bench.load_scene(good)
    assert st["SCENE_READY"] and not st["SCENE_ERROR"] and code == 0, f"good load after errors: STATUS {st}, code {code}"
    await _batch(bench, "after errors", rays, want)
    bench.monitor.check()


@cocotb.test()
async def abort_and_window(dut):
    """ABORT mid-batch (the rays handed out finish, the rest are not started), then the hit buffer outside the
    DMA window (refused: nothing written there, WINDOW_ERROR), then SOFT_RESET under a locked window that leaves
    out address 0; an exact batch after each."""
    bench = Bench(dut, "abort_and_window")
    await bench.reset()
    image = _image(bench)
    st, code = await bench.load_scene(image)
    assert st["SCENE_READY"] and code == 0, f"LOAD_SCENE: STATUS {st}, code {code}"
    rays, want = _golden(bench, "primary")
    ebits = bench.cfg["error_bits"]

    def written(what):
        """Hit records written (the rest keep the 0xa5 fill); each must be the golden one."""
        blob = bench.ddr.read(HIT_BASE, HIT_BYTES * len(rays))
        n = 0
        for i, ray in enumerate(rays):
            rec = blob[HIT_BYTES * i:HIT_BYTES * (i + 1)]
            if rec == bytes([0xa5]) * HIT_BYTES:
                continue
            got, junk = Hit.unpack(rec, ebits)
            assert got.number == i and not junk and agrees(ray, got, want[i]), f"{what}: ray {i}: hardware {got}, golden {want[i]}"
            n += 1
        return n

    async def start():
        bench.ddr.write(HIT_BASE, bytes([0xa5]) * (HIT_BYTES * len(rays)))
        bench.ddr.write(RAY_BASE, b"".join(r.record() for r in rays))
        await bench.write("RAY_BASE", RAY_BASE)
        await bench.write("RAY_COUNT", len(rays))
        await bench.write("HIT_BASE", HIT_BASE)
        await bench.write("IRQ_ENABLE", bench.bit("IRQ_ENABLE", "DONE"))
        await bench.write("CTRL", bench.bit("CTRL", "START"))

    async def end(what):
        await bench.wait_interrupt(400_000, what)
        await bench.write("IRQ_STATUS", await bench.read("IRQ_STATUS"))
        return await bench.read("STATUS")

    # ABORT a few hundred cycles into the batch.
    await start()
    await ClockCycles(bench.dut.aclk, 300)
    await bench.write("CTRL", bench.bit("CTRL", "ABORT"))
    status = await end("ABORT")
    issued, done = await bench.read("RAYS_ISSUED"), await bench.read("RAYS_DONE")
    aborted = bool(status & bench.bit("STATUS", "ABORTED"))
    assert aborted != bool(status & bench.bit("STATUS", "DONE")), f"ABORT: STATUS {status:#x}"
    assert done == issued <= len(rays), f"ABORT: RAYS_DONE {done}, RAYS_ISSUED {issued}"
    assert written("ABORT") == done, "ABORT: hit records written differ from RAYS_DONE"
    bench.log.info("ABORT after 300 cycles: %s, %d of %d rays issued and done", "ABORTED" if aborted else "DONE", issued, len(rays))
    await _batch(bench, "after ABORT", rays, want)

    # The hit buffer outside the window: every hit write refused.
    await bench.write("WINDOW_LIMIT", HIT_BASE)
    await start()
    status = await end("window")
    assert status & bench.bit("STATUS", "WINDOW_ERROR") and status & bench.bit("STATUS", "ABORTED"), f"window: STATUS {status:#x}"
    refused, first = await bench.read("WINDOW_REFUSED"), await bench.read("WINDOW_FAULT_ADDR")
    assert refused >= 1 and HIT_BASE <= first < HIT_BASE + HIT_BYTES * len(rays), f"window: {refused} refused, first at {first:#x}"
    assert bench.ddr.read(HIT_BASE, HIT_BYTES * len(rays)) == bytes([0xa5]) * (HIT_BYTES * len(rays)), "window: a hit written outside it"
    await bench.write("CTRL", bench.bit("CTRL", "START"))
    await ClockCycles(bench.dut.aclk, 20)
    assert not (await bench.read("STATUS")) & bench.bit("STATUS", "BUSY"), "START while WINDOW_ERROR is ignored"
    # A locked window that holds the scene, the rays and the hits but not address 0 (where a core's root fetch
    # points before a scene is loaded): SOFT_RESET keeps it, the load and the batch run inside it.
    lo, hi = SCENE_BASE & ~63, (HIT_BASE + HIT_BYTES * len(rays) + 63) & ~63
    await bench.write("WINDOW_BASE", lo)
    await bench.write("WINDOW_LIMIT", hi)
    await bench.write("WINDOW_LOCK", 1)
    for reg in ("WINDOW_BASE", "WINDOW_LIMIT", "WINDOW_LOCK"):
        bench.monitor.lite.slverr_expected += 1
        assert await bench.write_resp(reg, 0) == 2, f"a write to {reg} while locked: SLVERR expected"
    assert bench.monitor.lite.slverr_expected == 0, "the protocol monitor saw fewer SLVERR responses than refused writes"
    await bench.write("CTRL", bench.bit("CTRL", "SOFT_RESET"))
    assert await bench.read("STATUS") == 0, "STATUS after SOFT_RESET: no fault, no scene"
    assert (await bench.read("WINDOW_BASE"), await bench.read("WINDOW_LIMIT")) == (lo, hi), "SOFT_RESET keeps the locked window"
    st, code = await bench.load_scene(image)
    assert st["SCENE_READY"] and code == 0, f"LOAD_SCENE after SOFT_RESET in the locked window: STATUS {st}, code {code}"
    await _batch(bench, "in the locked window", rays, want)
    assert await bench.read("WINDOW_REFUSED") == 0, "a burst refused in the locked window"
    bench.monitor.check()
