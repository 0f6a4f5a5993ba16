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
    want = {"ID": 0x52544143, "VERSION": 1, "CONFIG_CORES": c["cores"], "CONFIG_LAYOUT": c["layout"],
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
        ("bad version", _corrupt(good, 8, 3), SCENE_BASE, codes["BAD_VERSION"]),
        ("other layout", _corrupt(good, 44, other_layout), SCENE_BASE, codes["LAYOUT"]),
        ("nodeBytes", _corrupt(good, 28, 32 * other_layout), SCENE_BASE, codes["RECORD_BYTES"]),
        ("triBytes", _corrupt(good, 32, 64), SCENE_BASE, codes["RECORD_BYTES"]),
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
