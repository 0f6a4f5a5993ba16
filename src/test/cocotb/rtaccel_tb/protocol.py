"""AXI4 and AXI4-Lite protocol assertions, written by us (not cocotbext-axi's).

One coroutine samples every channel of a port at each rising clock edge (the
values the flops see) and records any violation:

- every channel: once valid is high it stays high until ready, and the
  payload does not change while valid && !ready (AMBA AXI spec, A3.2.1);
- AR / AW of the AXI4 master: INCR bursts of full-width beats (the system
  contract: size = log2(data bytes), burst = INCR), len <= 255, no exclusive
  access, the start beat-aligned, and no burst crossing a 4 KB boundary (A3.4.1);
- W: each write burst has exactly awlen + 1 beats, wlast on the last one only
  (W may run ahead of its AW: bursts pair with AWs in order, A5.2);
- R: every beat's rid has an outstanding AR; rlast exactly on that burst's
  last beat (in order within an ID, any order across IDs);
- B: every bid belongs to a write whose AW and last W beat were both seen;
- AXI4-Lite: every R / B answers an outstanding AR / AW + W, with resp OKAY.

A violation is recorded with the cycle and the signals, and `check()` raises
them all; the first ones are also logged when they happen.
"""

import collections
import logging

OKAY = 0
SLVERR = 2
INCR = 1


class Violation(AssertionError):
    pass


class _Channel:
    """valid / ready / payload handles of one channel, and its stall state."""

    def __init__(self, dut, prefix, name, fields):
        self.name = f"{prefix}_{name}"
        self.valid = getattr(dut, f"{prefix}_{name}valid")
        self.ready = getattr(dut, f"{prefix}_{name}ready")
        self.fields = [(f, getattr(dut, f"{prefix}_{name}{f}")) for f in fields]
        self.held = None  # payload seen with valid && !ready at the last edge
        self.beats = 0
        self.stall_cycles = 0

    def payload(self):
        return {f: int(h.value) for f, h in self.fields}


class _Port:
    """The checks shared by both kinds of port: stability and valid persistence."""

    def __init__(self, dut, prefix, channels, log):
        self.prefix = prefix
        self.channels = {n: _Channel(dut, prefix, n, f) for n, f in channels.items()}
        self.violations = []
        self.log = log
        self.cycle = 0

    def fail(self, what):
        msg = f"{self.prefix} cycle {self.cycle}: {what}"
        if len(self.violations) < 20:
            self.log.error("AXI protocol violation: %s", msg)
        self.violations.append(msg)

    def sample(self, cycle):
        """One rising edge: returns {channel: payload} of the transfers that happen at it."""
        self.cycle = cycle
        fired = {}
        for n, ch in self.channels.items():
            valid = int(ch.valid.value)
            if ch.held is not None and not valid:
                self.fail(f"{ch.name}: valid dropped before ready (held {ch.held})")
            if not valid:
                ch.held = None
                continue
            p = ch.payload()
            if ch.held is not None and p != ch.held:
                diff = {k: (hex(ch.held[k]), hex(v)) for k, v in p.items() if ch.held[k] != v}
                self.fail(f"{ch.name}: payload changed while valid && !ready: {diff}")
            if int(ch.ready.value):
                ch.held = None
                ch.beats += 1
                fired[n] = p
            else:
                ch.held = p
                ch.stall_cycles += 1
        return fired


class Axi4Checker(_Port):
    """The AXI4 master port (the DUT issues AR / AW / W, answers R / B)."""

    def __init__(self, dut, prefix="m_axi", log=None):
        super().__init__(dut, prefix, {
            "aw": ["id", "addr", "len", "size", "burst", "lock", "cache", "prot", "qos"],
            "w": ["data", "strb", "last"],
            "b": ["id", "resp"],
            "ar": ["id", "addr", "len", "size", "burst", "lock", "cache", "prot", "qos"],
            "r": ["id", "data", "resp", "last"],
        }, log or logging.getLogger("cocotb.axi_protocol"))
        self.data_bytes = len(getattr(dut, f"{prefix}_wdata")) // 8
        self.beat_size = self.data_bytes.bit_length() - 1
        self.reads = collections.defaultdict(collections.deque)  # id -> beats left per outstanding AR, oldest first
        self.aw_lens = collections.deque()      # AWs whose W burst has not ended, in order
        self.w_bursts = collections.deque()     # ended W bursts (beat counts) with no AW yet
        self.w_count = 0                        # beats of the W burst in progress
        self.aw_pending = collections.deque()   # ids of AWs whose W burst has not been paired
        self.writes_open = collections.Counter()  # id -> writes with AW and last W, no B yet
        self.ar_count = 0
        self.aw_count = 0

    def _burst(self, kind, p):
        addr, length, size = p["addr"], p["len"], p["size"]
        if size != self.beat_size:
            self.fail(f"{kind} size {size}: beats must be full width (size {self.beat_size})")
        if p["burst"] != INCR:
            self.fail(f"{kind} burst type {p['burst']}: only INCR is allowed")
        if length > 255:
            self.fail(f"{kind} len {length} > 255")
        if p["lock"] != 0:
            self.fail(f"{kind} lock {p['lock']}: no exclusive accesses")
        if addr % self.data_bytes:
            self.fail(f"{kind} addr {addr:#x} is not aligned to the {self.data_bytes}-byte beat")
        end = addr + (length + 1) * self.data_bytes - 1
        if addr >> 12 != end >> 12:
            self.fail(f"{kind} addr {addr:#x} len {length}: the burst crosses a 4 KB boundary (ends at {end:#x})")

    def _pair_writes(self):
        while self.aw_lens and self.w_bursts:
            want, got = self.aw_lens.popleft(), self.w_bursts.popleft()
            awid = self.aw_pending.popleft()
            if want != got:
                self.fail(f"write burst id {awid:#x}: awlen + 1 = {want} beats, but wlast came on beat {got}")
            self.writes_open[awid] += 1

    def sample(self, cycle):
        fired = super().sample(cycle)
        if "ar" in fired:
            p = fired["ar"]
            self._burst("AR", p)
            self.reads[p["id"]].append(p["len"] + 1)
            self.ar_count += 1
        if "aw" in fired:
            p = fired["aw"]
            self._burst("AW", p)
            self.aw_lens.append(p["len"] + 1)
            self.aw_pending.append(p["id"])
            self.aw_count += 1
        if "w" in fired:
            self.w_count += 1
            # The AW of the burst in progress, if it came already: the first unpaired one.
            if not self.w_bursts and self.aw_lens and self.w_count > self.aw_lens[0]:
                self.fail(f"W burst runs past awlen + 1 = {self.aw_lens[0]} beats without wlast")
            if fired["w"]["last"]:
                self.w_bursts.append(self.w_count)
                self.w_count = 0
        self._pair_writes()
        if "r" in fired:
            p = fired["r"]
            q = self.reads.get(p["id"])
            if not q:
                self.fail(f"R beat with rid {p['id']:#x}: no outstanding AR has that id")
            else:
                q[0] -= 1
                if bool(p["last"]) != (q[0] == 0):
                    self.fail(f"R rid {p['id']:#x}: rlast = {p['last']} with {q[0]} beats of the burst left")
                if p["last"] or q[0] == 0:
                    q.popleft()
        if "b" in fired:
            bid = fired["b"]["id"]
            if self.writes_open[bid] <= 0:
                self.fail(f"B with bid {bid:#x}: no write with that id has both its AW and its last W beat")
            else:
                self.writes_open[bid] -= 1
        return fired

    def outstanding(self):
        """Transactions still open (reads, writes without B): expected 0 when the system is idle."""
        return sum(len(q) for q in self.reads.values()) + len(self.aw_lens) + sum(self.writes_open.values())


class AxiLiteChecker(_Port):
    """The AXI4-Lite slave port (the test bench is the master)."""

    def __init__(self, dut, prefix="s_axi", log=None):
        super().__init__(dut, prefix, {
            "aw": ["addr", "prot"], "w": ["data", "strb"], "b": ["resp"],
            "ar": ["addr", "prot"], "r": ["data", "resp"],
        }, log or logging.getLogger("cocotb.axil_protocol"))
        self.ar_open = 0
        self.aw_open = 0
        self.w_open = 0
        # Writes the test makes to be refused (a locked window register): that many SLVERR B responses are right.
        self.slverr_expected = 0

    def sample(self, cycle):
        fired = super().sample(cycle)
        self.ar_open += "ar" in fired
        self.aw_open += "aw" in fired
        self.w_open += "w" in fired
        if "r" in fired:
            if self.ar_open <= 0:
                self.fail("R without an outstanding AR")
            self.ar_open -= 1
            if fired["r"]["resp"] != OKAY:
                self.fail(f"R resp {fired['r']['resp']} (expected OKAY)")
        if "b" in fired:
            if self.aw_open <= 0 or self.w_open <= 0:
                self.fail(f"B without both an AW and a W outstanding (AW {self.aw_open}, W {self.w_open})")
            self.aw_open -= 1
            self.w_open -= 1
            if fired["b"]["resp"] == SLVERR and self.slverr_expected > 0:
                self.slverr_expected -= 1
            elif fired["b"]["resp"] != OKAY:
                self.fail(f"B resp {fired['b']['resp']} (expected OKAY)")
        return fired


class ProtocolMonitor:
    """Runs the checkers on every edge; counts cycles (the test's clock)."""

    def __init__(self, dut, clock):
        self.axi = Axi4Checker(dut)
        self.lite = AxiLiteChecker(dut)
        self.clock = clock
        self.cycle = 0
        self.reset = dut.aresetn

    async def run(self):
        # Sampled at the falling edge: everything has settled by then to the
        # values the next rising edge sees (the bench drives just after rising
        # edges). Sampling at the rising edge itself made the bench's writes of
        # that time step (aresetn) not take effect under Verilator 5.006's VPI.
        from cocotb.triggers import FallingEdge
        edge = FallingEdge(self.clock)
        while True:
            await edge
            self.cycle += 1
            if not int(self.reset.value):
                continue
            self.axi.sample(self.cycle)
            self.lite.sample(self.cycle)

    def check(self):
        bad = self.axi.violations + self.lite.violations
        if bad:
            raise Violation(f"{len(bad)} AXI protocol violations, first ones:\n  " + "\n  ".join(bad[:20]))
