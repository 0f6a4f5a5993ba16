// rtaccel-sim: one scene package through the Verilated rtaccel_system, driven
// by librtaccel exactly as a program on the board would drive it. Used by
// `make regress SIM=cpp` (src/main/scala/rtaccel/regress/CppSim.scala), which
// reads what this writes and makes the usual hits.csv and report.json:
//   OUT/hits.bin  the hit records as the hardware wrote them (32 B each, ray order)
//   OUT/sim.json  cycles, speed, the hardware's counters, the DDR model's statistics
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include "rays_csv.hpp"
#include "rtaccel.hpp"

namespace {

const char* kUsage =
    "usage: rtaccel-sim --package DIR --out DIR [--rays N] [--mem-latency NS|LO-HI] [--fabric-mhz 200]\n"
    "                   [--outstanding 64] [--seed 1] [--reorder 1] [--max-cycles N] [--vcd FILE]\n";

int usage(const std::string& why) {
  std::fprintf(stderr, "rtaccel-sim: %s\n%s", why.c_str(), kUsage);
  return 2;
}

bool parseUint(const std::string& s, unsigned long long& v) {
  char* end;
  errno = 0;
  v = std::strtoull(s.c_str(), &end, 10);
  return !s.empty() && !*end && errno == 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string pkg, out, vcd;
  unsigned long long maxRays = 0;
  rtaccel_sim_options o{};
  o.progress = 1;  // long batches show rays answered and an ETA on stderr
  for (int i = 1; i < argc; i += 2) {
    std::string k = argv[i];
    if (i + 1 >= argc) return usage("option " + k + " needs a value");
    std::string v = argv[i + 1];
    unsigned long long n = 0;
    if (k == "--package") pkg = v;
    else if (k == "--out") out = v;
    else if (k == "--vcd") vcd = v;
    else if (k == "--rays") { if (!parseUint(v, maxRays) || !maxRays) return usage("--rays: '" + v + "' is not a whole number >= 1"); }
    else if (k == "--fabric-mhz") { o.fabric_mhz = std::atof(v.c_str()); if (!(o.fabric_mhz > 0)) return usage("--fabric-mhz: '" + v + "'"); }
    else if (k == "--outstanding") { if (!parseUint(v, n) || !n) return usage("--outstanding: '" + v + "'"); o.max_outstanding = unsigned(n); }
    else if (k == "--seed") { o.seed = std::atoll(v.c_str()); }
    else if (k == "--reorder") { if (v != "0" && v != "1") return usage("--reorder: '" + v + "' (0 or 1)"); o.no_reorder = v == "0"; }
    else if (k == "--max-cycles") { if (!parseUint(v, n)) return usage("--max-cycles: '" + v + "'"); o.max_cycles = n; }
    else if (k == "--mem-latency") {
      unsigned lo = 0, hi = 0;
      int got = std::sscanf(v.c_str(), "%u-%u", &lo, &hi);
      if (got == 1) hi = lo;
      if (got < 1 || lo < 1 || hi < lo) return usage("--mem-latency: '" + v + "' (N or LO-HI in ns, 1 <= LO <= HI)");
      o.latency_ns_lo = lo;
      o.latency_ns_hi = hi;
    } else return usage("unknown option '" + k + "'");
  }
  if (pkg.empty() || out.empty()) return usage("--package and --out are required");
  if (!vcd.empty()) o.vcd_path = vcd.c_str();

  std::vector<rtaccel_ray> rays;
  std::string err;
  if (!rtaccel::sim::readRaysCsv(pkg + "/rays.csv", maxRays, rays, err)) {
    std::fprintf(stderr, "rtaccel-sim: %s\n", err.c_str());
    return 2;
  }
  if (rays.empty()) { std::fprintf(stderr, "rtaccel-sim: %s/rays.csv: no rays\n", pkg.c_str()); return 2; }

  auto t0 = std::chrono::steady_clock::now();
  rtaccel::Device dev;
  auto check = [&](rtaccel_status s, const char* what) {
    if (s == RTACCEL_OK) return;
    std::fprintf(stderr, "rtaccel-sim: %s: %s: %s\n", what, rtaccel_status_name(s), dev.lastError().c_str());
    std::exit(1);
  };
  check(rtaccel::Device::openSim(o, dev), "open");
  auto t1 = std::chrono::steady_clock::now();
  std::clock_t c1 = std::clock();
  check(dev.loadScene(pkg + "/image.bin"), "load scene");
  check(dev.submit(rays), "submit");
  check(dev.wait(), "wait");
  auto t2 = std::chrono::steady_clock::now();
  // CPU time too: on a shared machine wall time includes waiting for a core.
  double cpuSeconds = double(std::clock() - c1) / CLOCKS_PER_SEC;
  std::vector<rtaccel_hit> hits;
  check(dev.hits(hits, uint32_t(rays.size())), "read hits");
  rtaccel_counters c{};
  check(dev.counters(c), "read counters");
  uint64_t simCycles = 0;
  check(rtaccel_sim_cycles(dev.raw(), &simCycles), "cycles");
  check(rtaccel_sim_write_memory_json(dev.raw(), (out + "/sim-memory.json").c_str()), "memory json");

  {
    std::ofstream h(out + "/hits.bin", std::ios::binary);
    h.write(reinterpret_cast<const char*>(hits.data()), std::streamsize(hits.size() * sizeof(rtaccel_hit)));
    if (!h) { std::fprintf(stderr, "rtaccel-sim: %s/hits.bin: write failed\n", out.c_str()); return 1; }
  }
  double simSeconds = std::chrono::duration<double>(t2 - t1).count();
  double wall = std::chrono::duration<double>(t2 - t0).count();
  FILE* f = std::fopen((out + "/sim.json").c_str(), "w");
  if (!f) { std::fprintf(stderr, "rtaccel-sim: %s/sim.json: cannot write\n", out.c_str()); return 1; }
  std::fprintf(f, "{\n  \"rays\": %zu,\n  \"batchCycles\": %llu,\n  \"simulatedCycles\": %llu,\n", rays.size(),
               (unsigned long long)c.cycles, (unsigned long long)simCycles);
  std::fprintf(f, "  \"simulation\": {\"seconds\": %.6f, \"cyclesPerSecond\": %.1f, \"wallSeconds\": %.6f, "
               "\"cpuSeconds\": %.6f, \"cyclesPerCpuSecond\": %.1f, \"simulatedCycles\": %llu},\n", simSeconds,
               simCycles / (simSeconds > 0 ? simSeconds : 1e-9), wall, cpuSeconds,
               simCycles / (cpuSeconds > 0 ? cpuSeconds : 1e-9), (unsigned long long)simCycles);
  std::fprintf(f,
               "  \"counters\": {\"cycles\": %llu, \"raysIn\": %llu, \"hitsOut\": %llu, \"nodeFetches\": %llu, "
               "\"triFetches\": %llu, \"boxTests\": %llu, \"childBoxTests\": %llu, \"triTests\": %llu, \"decisions\": %llu, "
               "\"leafReturns\": %llu, \"nodeStoreHits\": %llu, \"nodeStoreMisses\": %llu, \"axiReadBeats\": %llu, "
               "\"axiWriteBeats\": %llu, \"axiReadStall\": %llu, \"inFlightSum\": %llu, \"raysDone\": %u},\n",
               (unsigned long long)c.cycles, (unsigned long long)c.rays_in, (unsigned long long)c.hits_out,
               (unsigned long long)c.node_fetches, (unsigned long long)c.tri_fetches, (unsigned long long)c.box_tests,
               (unsigned long long)c.child_box_tests, (unsigned long long)c.tri_tests, (unsigned long long)c.decisions,
               (unsigned long long)c.leaf_returns, (unsigned long long)c.node_store_hits,
               (unsigned long long)c.node_store_misses, (unsigned long long)c.axi_read_beats,
               (unsigned long long)c.axi_write_beats, (unsigned long long)c.axi_read_stall,
               (unsigned long long)c.in_flight_sum, c.rays_done);
  std::fprintf(f, "  \"errorCounts\": [%u, %u, %u, %u, %u]\n}\n", c.err_count[0], c.err_count[1], c.err_count[2],
               c.err_count[3], c.err_count[4]);
  std::fclose(f);
  std::printf("rtaccel-sim: %zu rays, %llu batch cycles, %llu simulated cycles in %.2f s (%.0f cycles/s; %.2f s of CPU, "
              "%.0f cycles per CPU second)\n", rays.size(), (unsigned long long)c.cycles, (unsigned long long)simCycles,
              simSeconds, simCycles / simSeconds, cpuSeconds, simCycles / cpuSeconds);
  return 0;
}
