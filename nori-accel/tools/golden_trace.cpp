// golden-trace <package dir> <hits.csv>: the golden walk (FP32 RTL,
// watertight, conservative boxes, stack 64) over a package's rays.
#include <cstdio>
#include <algorithm>
#include <exception>
#include <thread>

#include "../golden/package_io.h"

int main(int argc, char** argv) {
  if (argc != 3) { std::fprintf(stderr, "usage: golden-trace <package dir> <out hits.csv>\n"); return 2; }
  try {
    const std::string dir = argv[1];
    const rtg::Image img = rtg::read_image(dir + "/image.bin");
    const std::vector<rtg::RayIn> rays = rtg::read_rays_csv(dir + "/rays.csv");
    std::vector<rtg::HitOut> hits(rays.size());
    const rtg::WalkConfig cfg;
    // Rays are independent: split them over the machine's threads.
    const unsigned n = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned k = 0; k < n; ++k)
      pool.emplace_back([&, k] { for (size_t i = k; i < rays.size(); i += n) hits[i] = rtg::trace(img, rays[i], cfg); });
    for (auto& t : pool) t.join();
    rtg::write_hits_csv(argv[2], hits);
    std::printf("golden-trace: %zu rays -> %s\n", rays.size(), argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Error: %s\n", e.what());
    return 1;
  }
  return 0;
}
