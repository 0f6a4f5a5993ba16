// librtaccel's simulation backend: the driver's register accesses go through
// s_axi of the Verilated rtaccel_system, and its buffer is a window of the DDR
// model's memory (the host's copies into DDR take no simulated time, as a CPU
// writing its own DRAM does not stall the accelerator).
#include <cmath>
#include <cstdio>
#include <new>

#include "backend.h"
#include "rtaccel_regs.h"
#include "rtaccel_progress.hpp"
#include "sim_faults.hpp"
#include "system_sim.hpp"

using rtaccel::sim::AxiMemoryParams;
using rtaccel::sim::SystemSim;

namespace {

// The driver's buffer: 1 GiB at 256 MiB (a non-zero base, as on a board; sparse, so free until touched).
constexpr uint64_t kBufBase = 0x10000000, kBufSize = 0x40000000;

struct SimCtx {
  SystemSim sim;
  uint64_t maxCycles;
  bool progress;
  bool loseIrq = false;  // the next wait misses the interrupt (make faults)
  SimCtx(const AxiMemoryParams& p, const char* vcd, uint64_t maxCycles, bool progress)
      : sim(p, vcd), maxCycles(maxCycles), progress(progress) {}
};

template <class F>
rtaccel_status guard(char* err, size_t errn, F f) {
  try {
    return f();
  } catch (const std::exception& e) {
    std::snprintf(err, errn, "rtaccel sim: %s", e.what());
    return RTACCEL_ERR_DEVICE;
  }
}

rtaccel_status regRead(void* c, uint32_t off, uint32_t* v, char* err, size_t errn) {
  return guard(err, errn, [&] { *v = static_cast<SimCtx*>(c)->sim.readReg(off); return RTACCEL_OK; });
}
rtaccel_status regWrite(void* c, uint32_t off, uint32_t v, char* err, size_t errn) {
  return guard(err, errn, [&] { static_cast<SimCtx*>(c)->sim.writeReg(off, v); return RTACCEL_OK; });
}
rtaccel_status inBuffer(uint64_t addr, size_t n, char* err, size_t errn) {
  if (addr < kBufBase || addr + n > kBufBase + kBufSize) {
    std::snprintf(err, errn, "rtaccel sim: %zu bytes at 0x%llx lie outside the device buffer", n, (unsigned long long)addr);
    return RTACCEL_ERR_ARG;
  }
  return RTACCEL_OK;
}
rtaccel_status memWrite(void* c, uint64_t addr, const void* src, size_t n, char* err, size_t errn) {
  rtaccel_status s = inBuffer(addr, n, err, errn);
  if (s == RTACCEL_OK) static_cast<SimCtx*>(c)->sim.memory().memory().write(addr, src, n);
  return s;
}
rtaccel_status memRead(void* c, uint64_t addr, void* dst, size_t n, char* err, size_t errn) {
  rtaccel_status s = inBuffer(addr, n, err, errn);
  if (s == RTACCEL_OK) static_cast<SimCtx*>(c)->sim.memory().memory().read(addr, dst, n);
  return s;
}
// runUntilInterrupt(maxCycles) in slices of 2^16 cycles, showing between them the
// hit lines written so far: the "hits" region's write bytes since the batch
// started over one beat, as the system's WriteEngine writes each 64-byte line of
// two neighbouring 32-byte records (or one, strobes on its half) as a
// single-beat burst (the model counts whole beats); the bar's end is the
// batch's lines, a few short when a record had to leave without its neighbour.
// Observed in the memory model, so the simulated cycles and hits are the same
// as without it (checked: hits.bin and cycles equal on Cornell AO, 244,780 rays).
bool runShowingProgress(SimCtx& x) {
  const std::vector<rtaccel::sim::AxiMemory::Region>& regions = x.sim.memory().regions();
  const rtaccel::sim::AxiMemory::Region* hits = nullptr;
  for (const auto& r : regions) if (r.name == "hits") hits = &r;
  const auto written = [&] { return uint64_t(hits->writeBytes) / uint64_t(x.sim.memory().beatBytes()); };
  rtaccel::Progress bar("rtaccel sim:", hits ? (hits->hi - hits->lo + 63) / 64 : 0);
  const uint64_t start = x.sim.cycles(), slice = 1 << 16;
  for (;;) {
    const uint64_t left = x.maxCycles ? x.maxCycles - (x.sim.cycles() - start) : slice;
    if (x.sim.runUntilInterrupt(left < slice ? left : slice)) break;
    if (x.maxCycles && x.sim.cycles() - start >= x.maxCycles) return false;
    if (hits) bar.update(written());
  }
  if (hits) bar.finish(written());
  return true;
}

// A lost interrupt's wait runs this long when max_cycles sets no bound.
constexpr uint64_t kLostIrqCycles = 1 << 20;

rtaccel_status waitIrq(void* c, uint32_t, char* err, size_t errn) {
  auto* x = static_cast<SimCtx*>(c);
  return guard(err, errn, [&] {
    if (x->loseIrq) {
      x->loseIrq = false;
      const uint64_t n = x->maxCycles ? x->maxCycles : kLostIrqCycles;
      for (uint64_t i = 0; i < n; ++i) x->sim.step();
      std::snprintf(err, errn, "the interrupt was lost (make faults); %llu cycles passed", (unsigned long long)n);
      return RTACCEL_ERR_TIMEOUT;
    }
    if (x->progress ? runShowingProgress(*x) : x->sim.runUntilInterrupt(x->maxCycles)) return RTACCEL_OK;
    std::snprintf(err, errn, "%llu simulated cycles passed (rtaccel_sim_options.max_cycles)",
                  (unsigned long long)x->maxCycles);
    return RTACCEL_ERR_TIMEOUT;
  });
}
rtaccel_status simCycles(void* c, uint64_t* cycles) {
  *cycles = static_cast<SimCtx*>(c)->sim.cycles();
  return RTACCEL_OK;
}
rtaccel_status memoryJson(void* c, const char* path, char* err, size_t errn) {
  auto& m = static_cast<SimCtx*>(c)->sim.memory();
  FILE* f = std::fopen(path, "w");
  if (!f) {
    std::snprintf(err, errn, "%s: cannot write", path);
    return RTACCEL_ERR_FILE;
  }
  // The batch's share (from START), as the chiseltest harness counts a run.
  const auto b = m.sinceBatchStart();
  const auto& s = b.axi;
  auto& d = m.dram();
  std::fprintf(f, "{\n  \"totalCycles\": %lld,\n  \"batchCycles\": %lld,\n", (long long)m.now(), (long long)b.cycle);
  std::fprintf(f, "  \"dram\": {\"bytes\": %lld, \"bytesPerCycle\": %.6f, \"burstBytes\": %d, \"busyCycles\": %lld, "
               "\"totalBytes\": %lld},\n", (long long)b.dramBytes, d.bytesPerCycle(), d.burstBytes(),
               (long long)b.dramBusyCycles, (long long)d.bytes());
  std::fprintf(f, "  \"axi\": {\"beatBytes\": %d, \"readBursts\": %lld, \"readBeats\": %lld, \"writeBursts\": %lld, \"writeBeats\": %lld, "
               "\"readStallCycles\": %lld, \"readOutstandingSum\": %lld, \"nonOkayResponses\": %lld},\n",
               m.beatBytes(), (long long)s.readBursts, (long long)s.readBeats, (long long)s.writeBursts, (long long)s.writeBeats,
               (long long)s.readStallCycles, (long long)s.readOutstandingSum, (long long)s.nonOkayResponses);
  std::fprintf(f, "  \"regions\": {");
  const auto& rs = m.regions();
  for (size_t i = 0; i < rs.size(); ++i)
    std::fprintf(f, "%s\"%s\": {\"readBytes\": %lld, \"writeBytes\": %lld}", i ? ", " : "", rs[i].name.c_str(),
                 (long long)rs[i].readBytes, (long long)rs[i].writeBytes);
  std::fprintf(f, "},\n  \"violations\": [");
  const auto& v = m.violations();
  for (size_t i = 0; i < v.size(); ++i) std::fprintf(f, "%s\"%s\"", i ? ", " : "", v[i].c_str());
  std::fprintf(f, "]\n}\n");
  bool ok = std::fclose(f) == 0;
  if (!ok) {
    std::snprintf(err, errn, "%s: write failed", path);
    return RTACCEL_ERR_FILE;
  }
  return RTACCEL_OK;
}
void region(void* c, const char* name, uint64_t lo, uint64_t hi) {
  static_cast<SimCtx*>(c)->sim.memory().setRegion(name, lo, hi);
}
rtaccel_status simRun(void* c, uint64_t cycles, char* err, size_t errn) {
  auto* x = static_cast<SimCtx*>(c);
  return guard(err, errn, [&] {
    for (uint64_t i = 0; i < cycles; ++i) x->sim.step();
    return RTACCEL_OK;
  });
}
void batchStart(void* c) { static_cast<SimCtx*>(c)->sim.memory().batchStart(); }
void closeCtx(void* c) { delete static_cast<SimCtx*>(c); }

uint32_t axiDataBits(void*) { return uint32_t(rtaccel::sim::dutAxiDataBits()); }
const rtaccel_backend kSimBackend = {"sim", regRead, regWrite, memWrite, memRead, waitIrq, simCycles, memoryJson, region, batchStart, closeCtx,
                                     axiDataBits, simRun};

}  // namespace

extern "C" rtaccel_status rtaccel_open_sim(const rtaccel_sim_options* opt, rtaccel_dev** out) {
  if (!out) return RTACCEL_ERR_ARG;
  rtaccel_sim_options o{};
  if (opt) o = *opt;
  double mhz = o.fabric_mhz > 0 ? o.fabric_mhz : 200.0;
  double bps = o.ddr_bytes_per_s > 0 ? o.ddr_bytes_per_s : 12.8e9;
  uint32_t lo = o.latency_ns_lo ? o.latency_ns_lo : 100, hi = o.latency_ns_hi ? o.latency_ns_hi : lo;
  if (hi < lo) {
    rtaccel_set_open_error("rtaccel sim: latency %u-%u ns: need lo <= hi", lo, hi);
    return RTACCEL_ERR_ARG;
  }
  // ns to whole cycles, rounding up, as FabricClock.cycles (exact for integral ns * MHz / 1000).
  auto cycles = [&](uint32_t ns) {
    double c = std::ceil(ns * mhz / 1000.0 - 1e-9);
    return uint32_t(c < 1 ? 1 : c);
  };
  AxiMemoryParams p;
  p.bytesPerCycle = bps / (mhz * 1e6);
  p.burstBytes = o.burst_bytes ? int(o.burst_bytes) : 64;
  p.latencyLo = cycles(lo);
  p.latencyHi = cycles(hi);
  p.maxReads = p.maxWrites = o.max_outstanding ? o.max_outstanding : 64;
  p.reorder = !o.no_reorder;
  p.seed = o.seed ? o.seed : 1;
  SimCtx* c;
  try {
    c = new SimCtx(p, o.vcd_path, o.max_cycles, o.progress != 0);
    c->sim.reset();
    // What a board's privileged boot code does: confine the block's DMA to the driver's buffer, and lock it.
    c->sim.writeReg(RTACCEL_WINDOW_BASE_OFFSET, uint32_t(kBufBase));
    c->sim.writeReg(RTACCEL_WINDOW_LIMIT_OFFSET, uint32_t(kBufBase + kBufSize));
    c->sim.writeReg(RTACCEL_WINDOW_LOCK_OFFSET, RTACCEL_WINDOW_LOCK_LOCK_MASK);
  } catch (const std::exception& e) {
    rtaccel_set_open_error("rtaccel sim: %s", e.what());
    return RTACCEL_ERR_DEVICE;
  }
  return rtaccel_attach(&kSimBackend, c, kBufBase, kBufSize, out);
}

namespace rtaccel::sim {
SystemSim* systemOf(rtaccel_dev* dev) {
  auto* x = static_cast<SimCtx*>(rtaccel_backend_context(dev, &kSimBackend));
  return x ? &x->sim : nullptr;
}
bool loseNextInterrupt(rtaccel_dev* dev) {
  auto* x = static_cast<SimCtx*>(rtaccel_backend_context(dev, &kSimBackend));
  if (x) x->loseIrq = true;
  return x != nullptr;
}
}  // namespace rtaccel::sim
