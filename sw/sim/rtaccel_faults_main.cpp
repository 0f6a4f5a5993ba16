// make faults (docs/faults.md): faults injected into the simulated board, and
// librtaccel's recovery from each. A reference batch runs first (OUT/hits.bin,
// which the runner, rtaccel.regress.CppSimFaults, compares ray by ray with the
// golden model); then, per fault and trial, the fault is injected, the faulted
// operation must end cleanly (return within the bounds, block not BUSY), and
// the next batch must return the reference's hit records byte for byte.
// Then librtaccel under bad use: each misuse has its own code. Prints the
// table, writes it as markdown to REPORT, exits non-zero if any batch hung or
// any next batch differed.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "rays_csv.hpp"
#include "rtaccel.h"
#include "rtaccel_regs.h"
#include "sim_faults.hpp"
#include "system_sim.hpp"

using rtaccel::sim::AxiFault;
using rtaccel::sim::SystemSim;

namespace {

// The watchdog bound make faults sets (WATCHDOG_CYCLES), far above the reference batch's few thousand cycles
// between two events; the reset default (2^24) would only make each hang cost more simulated time.
constexpr uint32_t kWatchdog = 50000;
// The host's bound per wait (rtaccel_sim_options.max_cycles): 4 watchdog periods, so a hang the watchdog
// misses shows as a host timeout with the block still BUSY.
constexpr uint64_t kHostBound = 4 * uint64_t(kWatchdog);

struct Row {
  std::string fault;
  int tried = 0, clean = 0, hung = 0, exact = 0;
  uint64_t maxCycles = 0;  // longest faulted operation, cycles from its start to its return
};

struct Env {
  rtaccel_dev* dev;
  SystemSim* sim;
  std::vector<char> image;
  std::vector<rtaccel_ray> rays;
  std::vector<rtaccel_hit> ref;
  std::mt19937_64 rnd;
  uint64_t refCycles = 0;
};

const rtaccel::sim::AxiMemory::Region* region(Env& e, const char* name) {
  for (const auto& r : e.sim->memory().regions())
    if (r.name == name) return &r;
  return nullptr;
}

bool busy(Env& e) { return (e.sim->readReg(RTACCEL_STATUS_OFFSET) & RTACCEL_STATUS_BUSY_MASK) != 0; }

// The batch after recovery: OK and the reference's hits, byte for byte.
bool nextBatchExact(Env& e) {
  if (rtaccel_submit(e.dev, e.rays.data(), uint32_t(e.rays.size())) != RTACCEL_OK) return false;
  if (rtaccel_wait(e.dev, 0) != RTACCEL_OK) return false;
  std::vector<rtaccel_hit> hits(e.rays.size());
  if (rtaccel_read_hits(e.dev, hits.data(), uint32_t(hits.size())) != RTACCEL_OK) return false;
  return std::memcmp(hits.data(), e.ref.data(), hits.size() * sizeof(rtaccel_hit)) == 0;
}

// One trial: `run` injects and performs the faulted operation, returning whether it ended as the rule says.
void trial(Env& e, Row& row, const std::function<bool()>& run) {
  row.tried++;
  const uint64_t t0 = e.sim->cycles();
  bool clean = false;
  try {
    clean = run() && !busy(e);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "%s: %s\n", row.fault.c_str(), ex.what());
  }
  const uint64_t took = e.sim->cycles() - t0;
  row.maxCycles = std::max(row.maxCycles, took);
  e.sim->memory().inject(AxiFault{});  // a fault not met (its burst never came) does not outlive its trial
  if (clean) row.clean++;
  else {
    bool stillBusy = true;
    try { stillBusy = busy(e); } catch (const std::exception&) {}
    if (stillBusy) row.hung++;
    std::fprintf(stderr, "%s, trial %d: not clean (%s)\n", row.fault.c_str(), row.tried, rtaccel_last_error(e.dev));
  }
  // A scene fault leaves no scene: load it again, as a user would after RTACCEL_ERR_SCENE.
  bool exact = false;
  try {
    uint32_t st = e.sim->readReg(RTACCEL_STATUS_OFFSET);
    if (!(st & RTACCEL_STATUS_SCENE_READY_MASK)) rtaccel_load_scene(e.dev, e.image.data(), e.image.size());
    exact = nextBatchExact(e);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "%s: next batch: %s\n", row.fault.c_str(), ex.what());
  }
  if (exact) row.exact++;
  else std::fprintf(stderr, "%s, trial %d: next batch not exact (%s)\n", row.fault.c_str(), row.tried, rtaccel_last_error(e.dev));
}

// A fault on the bursts of one region: `skip` of them drawn at random among the first `span`.
AxiFault on(Env& e, const char* name, bool write, uint32_t resp, bool lost, uint32_t span) {
  const auto* r = region(e, name);
  AxiFault f;
  f.write = write;
  f.lo = r ? r->lo : 0;
  f.hi = r ? r->hi : 0;
  f.resp = resp;
  f.lost = lost;
  f.skip = uint32_t(e.rnd() % span);
  f.count = 1;
  return f;
}

// The loaded scene's regions, which librtaccel names when it loads it.
std::vector<uint64_t> sceneRegion(Env& e, const char* name) {
  const auto* r = region(e, name);
  return r ? std::vector<uint64_t>{r->lo, r->hi} : std::vector<uint64_t>{};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: rtaccel-faults PACKAGE_DIR OUT_DIR RAYS TRIALS SEED REPORT_MD\n");
    return 2;
  }
  const std::string pkg = argv[1], out = argv[2], report = argv[6];
  const size_t nRays = std::strtoul(argv[3], nullptr, 10);
  const int trials = std::atoi(argv[4]);
  const uint64_t seed = std::strtoull(argv[5], nullptr, 10);
  std::printf("rtaccel-faults: seed %" PRIu64 " (replay: FAULTS_SEED=%" PRIu64 ")\n", seed, seed);
  Env e{};
  e.rnd.seed(seed);
  std::string err;
  if (!rtaccel::sim::readRaysCsv(pkg + "/rays.csv", nRays, e.rays, err)) {
    std::fprintf(stderr, "rtaccel-faults: %s\n", err.c_str());
    return 2;
  }
  std::ifstream f(pkg + "/image.bin", std::ios::binary);
  e.image.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  if (e.image.size() < 64) {
    std::fprintf(stderr, "rtaccel-faults: %s/image.bin: missing or short (make it with nori-bridge compile)\n", pkg.c_str());
    return 2;
  }
  rtaccel_sim_options o{};
  o.max_cycles = kHostBound;
  o.seed = int64_t(seed);
  if (rtaccel_open_sim(&o, &e.dev) != RTACCEL_OK) {
    std::fprintf(stderr, "rtaccel-faults: open: %s\n", rtaccel_open_error());
    return 1;
  }
  e.sim = rtaccel::sim::systemOf(e.dev);
  e.sim->writeReg(RTACCEL_WATCHDOG_CYCLES_OFFSET, kWatchdog);
  const uint32_t n = uint32_t(e.rays.size());

  // ---- the reference batch ----
  if (rtaccel_load_scene(e.dev, e.image.data(), e.image.size()) != RTACCEL_OK ||
      rtaccel_submit(e.dev, e.rays.data(), n) != RTACCEL_OK) {
    std::fprintf(stderr, "rtaccel-faults: reference batch: %s\n", rtaccel_last_error(e.dev));
    return 1;
  }
  uint64_t c0 = e.sim->cycles();
  e.ref.resize(n);
  if (rtaccel_wait(e.dev, 0) != RTACCEL_OK || rtaccel_read_hits(e.dev, e.ref.data(), n) != RTACCEL_OK) {
    std::fprintf(stderr, "rtaccel-faults: reference batch: %s\n", rtaccel_last_error(e.dev));
    return 1;
  }
  e.refCycles = e.sim->cycles() - c0;
  {
    std::ofstream h(out + "/hits.bin", std::ios::binary);
    h.write(reinterpret_cast<const char*>(e.ref.data()), std::streamsize(n * sizeof(rtaccel_hit)));
  }
  std::printf("reference batch: %u rays, %" PRIu64 " cycles\n", n, e.refCycles);

  std::vector<Row> rows;
  auto run = [&](const std::string& name, const std::function<bool()>& body) {
    rows.push_back(Row{name});
    for (int t = 0; t < trials; ++t) trial(e, rows.back(), body);
  };
  auto batchFails = [&](rtaccel_status expect) {
    return rtaccel_submit(e.dev, e.rays.data(), n) == RTACCEL_OK && rtaccel_wait(e.dev, 0) == expect;
  };
  auto loadFails = [&](rtaccel_status expect) {
    return rtaccel_load_scene(e.dev, e.image.data(), e.image.size()) == expect;
  };
  // Bursts per region in one use: ray blocks (3 lines each, 4 rays), hit lines (one or two records each, so at
  // least ceil(n / 2) of them: a fault drawn among those is always met), the store fills' bursts.
  const uint32_t rayBursts = (n + 3) / 4, hitBursts = (n + 1) / 2;
  const auto nodes = sceneRegion(e, "nodes"), tris = sceneRegion(e, "triangles");
  const uint32_t nodeBursts = nodes.empty() ? 1 : uint32_t(std::max<uint64_t>(1, (nodes[1] - nodes[0]) / 4096));
  const uint32_t triBursts = tris.empty() ? 1 : uint32_t(std::max<uint64_t>(1, (tris[1] - tris[0]) / 4096));
  for (uint32_t resp : {2u, 3u}) {
    const std::string r = resp == 2 ? "SLVERR" : "DECERR";
    run(r + " on a node read", [&, resp] {
      e.sim->memory().inject(on(e, "nodes", false, resp, false, nodeBursts));
      return loadFails(RTACCEL_ERR_AXI);
    });
    run(r + " on a triangle read", [&, resp] {
      e.sim->memory().inject(on(e, "triangles", false, resp, false, triBursts));
      return loadFails(RTACCEL_ERR_AXI);
    });
    run(r + " on the scene header read", [&, resp] {
      e.sim->memory().inject(on(e, "header", false, resp, false, 1));
      return loadFails(RTACCEL_ERR_AXI);
    });
    run(r + " on a ray read", [&, resp] {
      e.sim->memory().inject(on(e, "rays", false, resp, false, rayBursts));
      return batchFails(RTACCEL_ERR_AXI);
    });
    run(r + " on a hit write", [&, resp] {
      e.sim->memory().inject(on(e, "hits", true, resp, false, hitBursts));
      return batchFails(RTACCEL_ERR_AXI);
    });
  }
  // A ray block that crosses a 4 KB page is read as two bursts of one ID. When the first is the one lost, the
  // model still answers the second, which AXI forbids (one ID answers in order): the ReadEngine reports that
  // beat as AXI_ERROR, so such a batch ends with AXI_ERROR beside TIMEOUT and librtaccel names the AXI error.
  run("a ray read never answered", [&] {
    e.sim->memory().inject(on(e, "rays", false, 0, true, rayBursts));
    if (rtaccel_submit(e.dev, e.rays.data(), n) != RTACCEL_OK) return false;
    const rtaccel_status s = rtaccel_wait(e.dev, 0);
    return s == RTACCEL_ERR_WATCHDOG || s == RTACCEL_ERR_AXI;
  });
  run("a hit write never answered", [&] {
    e.sim->memory().inject(on(e, "hits", true, 0, true, hitBursts));
    return batchFails(RTACCEL_ERR_WATCHDOG);
  });
  run("a node read never answered (scene load)", [&] {
    e.sim->memory().inject(on(e, "nodes", false, 0, true, nodeBursts));
    return loadFails(RTACCEL_ERR_WATCHDOG);
  });
  run("scene overwritten with NaNs mid-batch", [&] {
    if (rtaccel_submit(e.dev, e.rays.data(), n) != RTACCEL_OK) return false;
    rtaccel_sim_run(e.dev, e.rnd() % (e.refCycles + 1));
    std::vector<uint32_t> nan((nodes.empty() ? 0 : tris[1] - nodes[0]) / 4, 0x7fc00000u);
    if (!nan.empty()) e.sim->memory().memory().write(nodes[0], nan.data(), nan.size() * 4);
    rtaccel_status s = rtaccel_wait(e.dev, 0);
    // Ends either way: the node and triangle stores hold the scene's copy, so the batch may not see the NaNs.
    bool ok = s == RTACCEL_OK || s == RTACCEL_ERR_AXI;
    return loadFails(RTACCEL_OK) && ok;  // the user's recovery: the scene written and loaded again
  });
  run("ABORT at a random cycle", [&] {
    if (rtaccel_submit(e.dev, e.rays.data(), n) != RTACCEL_OK) return false;
    rtaccel_sim_run(e.dev, e.rnd() % (e.refCycles + 1));
    return rtaccel_abort(e.dev, 0) == RTACCEL_OK;
  });
  run("the interrupt lost", [&] {
    rtaccel::sim::loseNextInterrupt(e.dev);
    return batchFails(RTACCEL_OK);
  });

  // ---- bad use: each misuse its own code, the device usable after it ----
  struct Use { const char* what; rtaccel_status want; std::function<rtaccel_status()> call; };
  std::vector<char> raw((n + 1) * sizeof(rtaccel_ray));
  std::memcpy(raw.data() + 1, e.rays.data(), n * sizeof(rtaccel_ray));
  std::vector<char> otherLayout = e.image;
  otherLayout[44] = char(otherLayout[44] == 2 ? 8 : 2);  // header word 11: the node layout
  std::vector<rtaccel_hit> hits(n + 1);
  const std::vector<Use> uses = {
      {"null rays", RTACCEL_ERR_ARG, [&] { return rtaccel_submit(e.dev, nullptr, n); }},
      {"null device", RTACCEL_ERR_ARG, [&] { return rtaccel_submit(nullptr, e.rays.data(), n); }},
      {"misaligned rays", RTACCEL_ERR_ALIGN,
       [&] { return rtaccel_submit(e.dev, reinterpret_cast<const rtaccel_ray*>(raw.data() + 1), n); }},
      {"a batch larger than the hit buffer", RTACCEL_ERR_TOO_BIG, [&] { return rtaccel_submit(e.dev, e.rays.data(), 0xffffffffu); }},
      {"wait without a batch", RTACCEL_ERR_STATE, [&] { return rtaccel_wait(e.dev, 0); }},
      {"abort without a batch", RTACCEL_ERR_STATE, [&] { return rtaccel_abort(e.dev, 0); }},
      {"hits after an aborted batch", RTACCEL_ERR_STATE, [&] {
         rtaccel_submit(e.dev, e.rays.data(), n);
         rtaccel_abort(e.dev, 0);
         return rtaccel_read_hits(e.dev, hits.data(), n);
       }},
      {"more hits than the batch", RTACCEL_ERR_TOO_BIG, [&] {
         rtaccel_submit(e.dev, e.rays.data(), n);
         rtaccel_wait(e.dev, 0);
         return rtaccel_read_hits(e.dev, hits.data(), n + 1);
       }},
      {"a scene of another layout", RTACCEL_ERR_LAYOUT,
       [&] { return rtaccel_load_scene(e.dev, otherLayout.data(), otherLayout.size()); }},
      {"submit after a failed scene load", RTACCEL_ERR_NO_SCENE, [&] { return rtaccel_submit(e.dev, e.rays.data(), n); }},
  };
  int misuseBad = 0;
  std::printf("\nbad use:\n");
  for (const auto& u : uses) {
    rtaccel_status s = u.call();
    bool ok = s == u.want;
    if (!ok) misuseBad++;
    std::printf("  %-36s %-22s %s\n", u.what, rtaccel_status_name(s), ok ? "ok" : "FAIL");
  }
  Row after{"after the bad use (scene loaded again)"};
  trial(e, after, [&] { return rtaccel_load_scene(e.dev, e.image.data(), e.image.size()) == RTACCEL_OK; });
  rows.push_back(after);

  // ---- the table ----
  int bad = misuseBad;
  std::string md = "| fault | batches tried | ended cleanly | hung | next batch exact | longest, cycles |\n"
                   "| --- | ---: | ---: | ---: | ---: | ---: |\n";
  std::printf("\n%-42s %6s %6s %5s %6s %10s\n", "fault", "tried", "clean", "hung", "exact", "max cyc");
  for (const auto& r : rows) {
    std::printf("%-42s %6d %6d %5d %6d %10" PRIu64 "\n", r.fault.c_str(), r.tried, r.clean, r.hung, r.exact, r.maxCycles);
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %d | %d | %d | %d | %" PRIu64 " |\n", r.fault.c_str(), r.tried, r.clean, r.hung,
                  r.exact, r.maxCycles);
    md += line;
    if (r.clean != r.tried || r.hung || r.exact != r.tried) bad++;
  }
  FILE* m = std::fopen(report.c_str(), "w");
  if (!m) {
    std::fprintf(stderr, "rtaccel-faults: %s: cannot write\n", report.c_str());
    return 1;
  }
  std::fprintf(m,
               "# Faults injected into the board simulation (`make faults`)\n\n"
               "Generated by `make faults` (rtaccel-faults, %d trials per fault, seed %" PRIu64 "; the rules and the method "
               "in docs/faults.md). Do not edit by hand.\n\n"
               "Cornell box, %u camera rays a batch; the reference batch: %" PRIu64 " cycles (its hits checked ray by ray "
               "against the golden model by rtaccel.regress.CppSimFaults, which fails otherwise). "
               "Watchdog %u cycles. Bad use of librtaccel: %d of %zu misuses returned a wrong code.\n\n%s",
               trials, seed, n, e.refCycles, kWatchdog, misuseBad, uses.size(), md.c_str());
  std::fclose(m);
  std::printf("\nrtaccel-faults: %d rows or misuses failed; table in %s\n", bad, report.c_str());
  rtaccel_close(e.dev);
  return bad ? 1 : 0;
}
