"""The DDR behind m_axi: cocotbext-axi's AxiRam, with reordered, delayed reads.

cocotbext-axi's AxiRam serves AR requests strictly in order, one burst at a
time, with no latency of its own; it has no option to reorder by ID. The
system contract lets reads return out of order across IDs (a MIG does), so the
read side here keeps AxiRam's memory, channels and address checks and replaces
only its scheduler: every accepted AR waits a random latency, and among the
requests whose latency has passed, the oldest of each ID is eligible (in order
within an ID) and one is drawn at random. Bursts are not interleaved beat by
beat (the contract allows reordering across IDs, not interleaving).
Back-pressure on every channel comes from cocotbext-axi's pause generators.
"""

import logging

from cocotb.triggers import RisingEdge
from cocotb.utils import get_sim_time
from cocotbext.axi import AxiBus
from cocotbext.axi.axi_ram import AxiRamRead, AxiRamWrite
from cocotbext.axi.constants import AxiResp
from cocotbext.axi.memory import Memory


class ReorderingRead(AxiRamRead):
    def __init__(self, bus, clock, reset, mem, rng, period_ns, latency):
        # Set before the base class starts _process_read (it does so at once if reset is inactive).
        self.rng = rng
        self.period_ns = period_ns
        self.latency = latency
        self.reordered = 0   # bursts served before an older burst of another ID
        self.served = 0
        super().__init__(bus, clock, reset, reset_active_level=False, mem=mem)

    def _now(self):
        return get_sim_time("ns")

    def _take(self, pool, seq):
        while not self.ar_channel.empty():
            ar = self.ar_channel.recv_nowait()
            due = self._now() + self.period_ns * self.rng.randint(*self.latency)
            pool.append((due, seq[0], ar))
            seq[0] += 1

    async def _process_read(self):
        pool, seq = [], [0]
        edge = RisingEdge(self.clock)
        while True:
            self._take(pool, seq)
            if not pool:
                ar = await self.ar_channel.recv()
                pool.append((self._now() + self.period_ns * self.rng.randint(*self.latency), seq[0], ar))
                seq[0] += 1
                continue
            oldest = {}
            for e in pool:
                i = int(e[2].arid)
                if i not in oldest or e[1] < oldest[i][1]:
                    oldest[i] = e
            due = [e for e in oldest.values() if e[0] <= self._now()]
            if not due:
                await edge
                continue
            pick = self.rng.choice(sorted(due, key=lambda e: e[1]))
            if pick[1] != min(e[1] for e in pool):
                self.reordered += 1
            pool.remove(pick)
            self.served += 1
            await self._serve(pick[2], pool, seq)

    async def _serve(self, ar, pool, seq):
        arid, addr, length = int(ar.arid), int(ar.araddr), int(ar.arlen) + 1
        size = int(ar.arsize)
        # The protocol monitor reports illegal sizes and 4 KB crossings; serve full beats regardless.
        beat = 2 ** size if 0 < 2 ** size <= self.byte_lanes else self.byte_lanes
        cur = (addr // beat) * beat
        for n in range(length):
            r = self.r_channel._transaction_obj()
            r.rid = arid
            r.rlast = n == length - 1
            r.rresp = AxiResp.OKAY
            word = (cur // self.byte_lanes) * self.byte_lanes
            r.rdata = int.from_bytes(await self._read(word, self.byte_lanes), "little")
            await self.r_channel.send(r)
            self._take(pool, seq)
            cur += beat


class Ddr(Memory):
    """AxiRam-equivalent: one memory, cocotbext-axi's write side, the reordering read side."""

    def __init__(self, dut, clock, size, rng, period_ns, latency=(0, 24)):
        super().__init__(size)
        bus = AxiBus.from_prefix(dut, "m_axi")
        self.write_if = AxiRamWrite(bus.write, clock, dut.aresetn, reset_active_level=False, mem=self.mem)
        self.read_if = ReorderingRead(bus.read, clock, dut.aresetn, self.mem, rng, period_ns, latency)
        for side in (self.write_if, self.read_if):
            side.log.setLevel(logging.WARNING)  # one INFO line per burst otherwise

    def back_pressure(self, gen):
        """A pause generator (from `gen()`) on every m_axi channel: AR, R, AW, W, B."""
        for ch in (self.read_if.ar_channel, self.read_if.r_channel, self.write_if.aw_channel,
                   self.write_if.w_channel, self.write_if.b_channel):
            ch.set_pause_generator(gen())
