"""The bench around rtaccel_system: clock, reset, the DDR model on m_axi, the
AXI4-Lite master on s_axi, the protocol monitor, and the driver's register
sequence (system contract, "Driver sequence")."""

import json
import logging
import os
import random
import zlib

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, RisingEdge
from cocotbext.axi import AxiLiteBus, AxiLiteMaster

from .ddr import Ddr
from .protocol import ProtocolMonitor
from .regs import RegMap

PERIOD_NS = 5  # 200 MHz fabric clock
MEM_BYTES = 1 << 24
# Buffers in the model DDR, 64-byte aligned, far apart; none starts on a 4 KB
# boundary, so a DMA that does not split its bursts there is caught.
SCENE_BASE = 0x0010_0040
RAY_BASE = 0x0040_0fc0
HIT_BASE = 0x0060_0f80
CANARY = 0xA5


def seed_for(name):
    """RTACCEL_SEED if set, else a stable hash of the test name (printed by every test)."""
    env = os.environ.get("RTACCEL_SEED", "").strip()
    return int(env) if env else zlib.crc32(name.encode())


def pauses(rng, busy):
    """An endless pause pattern: stretches of 1..48 cycles, each with its own
    pause probability drawn from `busy` (0 = free-flowing, 0.9 = nearly stalled)."""
    while True:
        p = rng.choice(busy)
        for _ in range(rng.randint(1, 48)):
            yield rng.random() < p


class Bench:
    def __init__(self, dut, test_name, busy=(0.0, 0.2, 0.5, 0.9), latency=(0, 24)):
        self.dut = dut
        self.log = logging.getLogger(f"cocotb.test.{test_name}")
        path = os.environ.get("RTACCEL_COCOTB_CONFIG")
        if not path or not os.path.exists(path):
            raise FileNotFoundError(f"RTACCEL_COCOTB_CONFIG={path!r}: no config.json (run `make test-cocotb`, which writes it)")
        with open(path) as f:
            self.cfg = json.load(f)
        self.dir = os.path.dirname(path)
        self.regs = RegMap(self.cfg["registers"])
        self.seed = seed_for(test_name)
        self.log.info("seed %d (replay: RTACCEL_SEED=%d make test-cocotb)", self.seed, self.seed)
        self.rng = random.Random(self.seed)
        cocotb.start_soon(Clock(dut.aclk, PERIOD_NS, units="ns").start())
        self.ddr = Ddr(dut, dut.aclk, MEM_BYTES, random.Random(self.rng.getrandbits(64)), PERIOD_NS, latency)
        self.ddr.write(0, bytes([CANARY]) * MEM_BYTES)
        self.lite = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axi"), dut.aclk, dut.aresetn, reset_active_level=False)
        for side in (self.lite.write_if, self.lite.read_if):
            side.log.setLevel(logging.WARNING)
        prng = random.Random(self.rng.getrandbits(64))
        self.ddr.back_pressure(lambda: pauses(random.Random(prng.getrandbits(64)), busy))
        for ch in (self.lite.write_if.aw_channel, self.lite.write_if.w_channel, self.lite.write_if.b_channel,
                   self.lite.read_if.ar_channel, self.lite.read_if.r_channel):
            ch.set_pause_generator(pauses(random.Random(prng.getrandbits(64)), busy))
        self.monitor = ProtocolMonitor(dut, dut.aclk)
        cocotb.start_soon(self.monitor.run())

    async def reset(self):
        self.dut.aresetn.value = 0
        await ClockCycles(self.dut.aclk, 16)
        self.dut.aresetn.value = 1
        await ClockCycles(self.dut.aclk, 4)

    # --- registers -------------------------------------------------------
    async def write(self, reg, value):
        await self.lite.write_dword(self.regs.offset(reg), value)

    async def write_resp(self, reg, value):
        """A register write; returns its BRESP (0 OKAY, 2 SLVERR)."""
        r = await self.lite.write(self.regs.offset(reg), value.to_bytes(4, "little"))
        return int(r.resp)

    async def read(self, reg):
        return await self.lite.read_dword(self.regs.offset(reg))

    async def read64(self, name):
        lo = await self.read(f"{name}_LO")  # latches _HI
        hi = await self.read(f"{name}_HI")
        return hi << 32 | lo

    def bit(self, reg, field):
        return self.regs.mask(reg, field)

    async def status(self):
        s = await self.read("STATUS")
        return {f: bool(s & self.bit("STATUS", f)) for f in ("BUSY", "DONE", "SCENE_READY", "SCENE_ERROR", "BROKEN", "AXI_ERROR")}

    async def wait_interrupt(self, max_cycles, what):
        """Waits for `interrupt` high, at most max_cycles (a cycle bound: never a wall-clock one)."""
        for n in range(max_cycles):
            if int(self.dut.interrupt.value):
                return n
            await RisingEdge(self.dut.aclk)
        self.monitor.check()  # a protocol violation is the likelier cause: report it first
        raise AssertionError(f"{what}: no interrupt within {max_cycles} cycles (STATUS {await self.status()})")

    async def quiet(self, cycles):
        """Waits `cycles` cycles and checks `interrupt` stayed low."""
        for _ in range(cycles):
            assert not int(self.dut.interrupt.value), "interrupt rose with no cause enabled and pending"
            await RisingEdge(self.dut.aclk)

    # --- the driver's sequence ----------------------------------------------
    async def load_scene(self, image: bytes, base=SCENE_BASE, max_cycles=100_000):
        """Copies image.bin, LOAD_SCENE, waits for the SCENE interrupt and clears it; returns (status, code)."""
        self.ddr.write(base, image)
        await self.write("SCENE_BASE", base)
        await self.write("IRQ_ENABLE", self.bit("IRQ_ENABLE", "DONE") | self.bit("IRQ_ENABLE", "SCENE"))
        await self.write("CTRL", self.bit("CTRL", "LOAD_SCENE"))
        await self.wait_interrupt(max_cycles, "LOAD_SCENE")
        irq = await self.read("IRQ_STATUS")
        assert irq & self.bit("IRQ_STATUS", "SCENE"), f"interrupt after LOAD_SCENE, but IRQ_STATUS = {irq:#x}"
        assert not irq & self.bit("IRQ_STATUS", "DONE"), f"IRQ_STATUS.DONE set by a scene load: {irq:#x}"
        await self.write("IRQ_STATUS", self.bit("IRQ_STATUS", "SCENE"))
        await RisingEdge(self.dut.aclk)
        assert not int(self.dut.interrupt.value), "interrupt still high after IRQ_STATUS.SCENE was cleared"
        return await self.status(), await self.read("SCENE_ERROR_CODE")

    async def run_batch(self, rays, max_cycles=400_000):
        """Writes the rays, START, waits for the DONE interrupt and clears it; returns (hit records, cycles waited)."""
        blob = b"".join(r.record() for r in rays)
        self.ddr.write(RAY_BASE, blob)
        await self.write("RAY_BASE", RAY_BASE)
        await self.write("RAY_COUNT", len(rays))
        await self.write("HIT_BASE", HIT_BASE)
        await self.write("IRQ_ENABLE", self.bit("IRQ_ENABLE", "DONE") | self.bit("IRQ_ENABLE", "SCENE"))
        await self.write("CTRL", self.bit("CTRL", "START"))
        cycles = await self.wait_interrupt(max_cycles, f"batch of {len(rays)} rays")
        irq = await self.read("IRQ_STATUS")
        assert irq & self.bit("IRQ_STATUS", "DONE"), f"interrupt after START, but IRQ_STATUS = {irq:#x}"
        await self.write("IRQ_STATUS", self.bit("IRQ_STATUS", "DONE"))
        await RisingEdge(self.dut.aclk)
        assert not int(self.dut.interrupt.value), "interrupt still high after IRQ_STATUS.DONE was cleared"
        return self.ddr.read(HIT_BASE, 32 * len(rays)), cycles

    def untouched(self, keep):
        """Every byte outside `keep` ([(base, bytes)], the buffers the test wrote or the DUT may write) still holds the canary."""
        bad = []
        spans = sorted(keep)
        pos = 0
        for base, n in spans + [(MEM_BYTES, 0)]:
            if base > pos:
                chunk = self.ddr.read(pos, base - pos)
                stray = chunk.strip(bytes([CANARY]))
                if stray:
                    first = pos + next(i for i, b in enumerate(chunk) if b != CANARY)
                    bad.append(f"{first:#x}")
            pos = max(pos, base + n)
        return bad
