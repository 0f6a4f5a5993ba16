// golden-trace <package dir> <hits.csv>: the golden walk (FP32 RTL,
// watertight, conservative boxes, stack 64) over a package's rays.
// golden-trace --rtl-hits <package dir> <hits.bin> <hits.csv>: the hit
// records the hardware wrote (rtaccel-sim's hits.bin, 32 bytes each, ray
// order) as a hits.csv, each checked against the golden walk as make regress
// checks them (TraversalGolden.agrees: hit, t/u/v bits, prim and error bits;
// shadow rays: occlusion and error bits). Exits 1 if any ray differs.
#include <cstdio>
#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <thread>

#include "../golden/package_io.h"
#include "../../hls/fp32.h"
#include "../../sw/include/rtaccel_progress.hpp"

namespace {
// The golden walk over every ray, split over the machine's threads (rays are independent).
std::vector<rtg::HitOut> trace_all(const rtg::Image& img, const std::vector<rtg::RayIn>& rays) {
  std::vector<rtg::HitOut> hits(rays.size());
  const rtg::WalkConfig cfg;
  const unsigned n = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  // Long runs (large scenes, many rays) show rays traced / total and an ETA on stderr.
  rtaccel::Progress bar("golden-trace:", rays.size());
  std::atomic<uint64_t> done{0};
  constexpr size_t kReport = 4096;  // rays a thread traces between looks at the clock
  for (unsigned k = 0; k < n; ++k)
    pool.emplace_back([&, k] {
      size_t mine = 0;
      for (size_t i = k; i < rays.size(); i += n) {
        hits[i] = rtg::trace(img, rays[i], cfg);
        if (++mine == kReport) bar.update(done += mine), mine = 0;
      }
      done += mine;
    });
  for (auto& t : pool) t.join();
  bar.finish(done);
  return hits;
}

uint32_t u32(const uint8_t* p) { uint32_t v; std::memcpy(&v, p, 4); return v; }
float f32(const uint8_t* p) { float v; std::memcpy(&v, p, 4); return v; }

// The hardware's hit records (system contract: number, status (bit 0 hit, bits 8.. errors), t, u, v, prim, 2 reserved).
std::vector<rtg::HitOut> read_hits_bin(const std::string& path, size_t rays) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open");
  const std::vector<uint8_t> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (b.size() != 32 * rays)
    throw std::runtime_error(path + ": " + std::to_string(b.size()) + " bytes, expected " + std::to_string(rays) + " hit records of 32 bytes");
  std::vector<rtg::HitOut> hits(rays);
  for (size_t i = 0; i < rays; ++i) {
    const uint8_t* r = &b[32 * i];
    if (u32(r) != i) throw std::runtime_error(path + ": record " + std::to_string(i) + " carries ray number " + std::to_string(u32(r)));
    const uint32_t status = u32(r + 4);
    rtg::HitOut& h = hits[i];
    h.hit = (status & 1) != 0;
    h.t = f32(r + 8);
    h.u = f32(r + 12);
    h.v = f32(r + 16);
    h.prim = h.hit ? static_cast<int64_t>(u32(r + 20)) : -1;
    h.errors = (status >> 8) & 0xff;
  }
  return hits;
}

bool agrees(const rtg::RayIn& r, const rtg::HitOut& a, const rtg::HitOut& g) {
  if (a.hit != g.hit || a.errors != g.errors) return false;
  if (r.shadow || !a.hit) return true;
  return rt::bits(a.t) == rt::bits(g.t) && rt::bits(a.u) == rt::bits(g.u) && rt::bits(a.v) == rt::bits(g.v) && a.prim == g.prim;
}
}  // namespace

int main(int argc, char** argv) {
  const bool rtl = argc == 5 && std::strcmp(argv[1], "--rtl-hits") == 0;
  if (argc != 3 && !rtl) {
    std::fprintf(stderr, "usage: golden-trace <package dir> <out hits.csv> | --rtl-hits <package dir> <hits.bin> <out hits.csv>\n");
    return 2;
  }
  try {
    const std::string dir = argv[rtl ? 2 : 1];
    const rtg::Image img = rtg::read_image(dir + "/image.bin");
    const std::vector<rtg::RayIn> rays = rtg::read_rays_csv(dir + "/rays.csv");
    const std::vector<rtg::HitOut> golden = trace_all(img, rays);
    if (!rtl) {
      rtg::write_hits_csv(argv[2], golden);
      std::printf("golden-trace: %zu rays -> %s\n", rays.size(), argv[2]);
      return 0;
    }
    const std::vector<rtg::HitOut> hw = read_hits_bin(argv[3], rays.size());
    size_t bad = 0;
    for (size_t i = 0; i < rays.size(); ++i)
      if (!agrees(rays[i], hw[i], golden[i]) && ++bad <= 10)
        std::printf("golden-trace: GOLDEN MISMATCH %s ray %zu: hardware hit %d t %a u %a v %a prim %lld errors %u, golden hit %d t %a "
                    "u %a v %a prim %lld errors %u\n", dir.c_str(), i, hw[i].hit, hw[i].t, hw[i].u, hw[i].v, (long long)hw[i].prim,
                    hw[i].errors, golden[i].hit, golden[i].t, golden[i].u, golden[i].v, (long long)golden[i].prim, golden[i].errors);
    rtg::write_hits_csv(argv[4], hw);
    std::printf("golden-trace: %s: %zu hardware hits -> %s, %zu differ from the golden walk\n", argv[3], rays.size(), argv[4], bad);
    return bad == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Error: %s\n", e.what());
    return 1;
  }
}
