// librtaccel against the Verilated rtaccel_system: the driver sequence on a
// scene package, then the error paths. Writes OUT/hits.bin, which
// CppSimSpec's runner (rtaccel.regress.CppSimTest) compares ray by ray with
// the golden model. Exits non-zero on the first failed expectation, saying
// which.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "rays_csv.hpp"
#include "rtaccel.h"
#include "rtaccel.hpp"
#include "rtaccel_regs.h"
#include "system_sim.hpp"

namespace {

int failures = 0;
void expect(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  if (!ok) failures++;
}
std::string named(rtaccel_status s) { return rtaccel_status_name(s); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: test-librtaccel PACKAGE_DIR OUT_DIR RAYS\n");
    return 2;
  }
  std::string pkg = argv[1], out = argv[2];
  size_t nRays = std::strtoul(argv[3], nullptr, 10);
  std::vector<rtaccel_ray> rays;
  std::string err;
  if (!rtaccel::sim::readRaysCsv(pkg + "/rays.csv", nRays, rays, err)) {
    std::fprintf(stderr, "test-librtaccel: %s\n", err.c_str());
    return 2;
  }
  std::ifstream f(pkg + "/image.bin", std::ios::binary);
  std::vector<char> image((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (image.size() < 64) {
    std::fprintf(stderr, "test-librtaccel: %s/image.bin: missing or short (make it with nori-bridge compile)\n", pkg.c_str());
    return 2;
  }

  // Through the C API.
  rtaccel_sim_options o{};
  o.max_cycles = 50000000;  // a hang fails the test instead of running forever
  rtaccel_dev* dev = nullptr;
  rtaccel_status s = rtaccel_open_sim(&o, &dev);
  expect(s == RTACCEL_OK, "open the simulated system: " + named(s) + " " + rtaccel_open_error());
  if (s != RTACCEL_OK) return 1;
  rtaccel_info info{};
  s = rtaccel_info_get(dev, &info);
  expect(s == RTACCEL_OK && info.id == RTACCEL_ID_VALUE && info.version == RTACCEL_VERSION_VALUE && info.cores >= 1 &&
             info.axi_data_bits == uint32_t(rtaccel::sim::dutAxiDataBits()),
         "ID, VERSION and CONFIG registers (cores " + std::to_string(info.cores) + ", ray IDs " +
             std::to_string(info.ray_ids) + ", m_axi " + std::to_string(info.axi_data_bits) + " bits, the model's " +
             std::to_string(rtaccel::sim::dutAxiDataBits()) + ")");

  // Error paths before a scene.
  s = rtaccel_submit(dev, rays.data(), 1);
  expect(s == RTACCEL_ERR_NO_SCENE, "submit before a scene: " + named(s));
  std::string missing = pkg + "/no-such-image.bin";
  s = rtaccel_load_scene_file(dev, missing.c_str());
  expect(s == RTACCEL_ERR_FILE && std::strstr(rtaccel_last_error(dev), missing.c_str()),
         "a missing package file: " + named(s) + ", message '" + rtaccel_last_error(dev) + "'");
  std::string notImage = pkg + "/rays.csv";
  s = rtaccel_load_scene_file(dev, notImage.c_str());
  expect(s == RTACCEL_ERR_FILE && std::strstr(rtaccel_last_error(dev), notImage.c_str()),
         "a file that is not an image: " + named(s) + ", message '" + rtaccel_last_error(dev) + "'");
  std::vector<char> bad = image;
  bad[0] = 'X';
  s = rtaccel_load_scene(dev, bad.data(), bad.size());
  expect(s == RTACCEL_ERR_SCENE && rtaccel_scene_error(dev) == RTACCEL_SCENE_BAD_MAGIC,
         "bad magic surfaces SCENE_ERROR: " + named(s) + ", code " + std::to_string(rtaccel_scene_error(dev)) + " '" +
             rtaccel_last_error(dev) + "'");
  bad = image;
  bad[8] = 99;  // version word
  s = rtaccel_load_scene(dev, bad.data(), bad.size());
  expect(s == RTACCEL_ERR_SCENE && rtaccel_scene_error(dev) == RTACCEL_SCENE_BAD_VERSION,
         "bad version surfaces SCENE_ERROR: " + named(s) + ", code " + std::to_string(rtaccel_scene_error(dev)));
  s = rtaccel_submit(dev, rays.data(), 1);
  expect(s == RTACCEL_ERR_NO_SCENE, "submit after a refused scene: " + named(s));
  expect(rtaccel_load_scene(nullptr, image.data(), image.size()) == RTACCEL_ERR_ARG &&
             rtaccel_submit(dev, nullptr, 1) == RTACCEL_ERR_ARG,
         "null arguments give RTACCEL_ERR_ARG");

  // The batch.
  s = rtaccel_load_scene_file(dev, pkg.c_str());
  expect(s == RTACCEL_OK, "load " + pkg + ": " + named(s) + " " + rtaccel_last_error(dev));
  if (s != RTACCEL_OK) return 1;
  s = rtaccel_submit(dev, rays.data(), uint32_t(rays.size()));
  expect(s == RTACCEL_OK, "submit " + std::to_string(rays.size()) + " rays: " + named(s) + " " + rtaccel_last_error(dev));
  rtaccel_status busy = rtaccel_submit(dev, rays.data(), 1);
  expect(busy == RTACCEL_ERR_BUSY, "a second submit while the batch runs: " + named(busy));
  s = rtaccel_wait(dev, 0);
  expect(s == RTACCEL_OK, "wait: " + named(s) + " " + rtaccel_last_error(dev));
  if (s != RTACCEL_OK) return 1;
  std::vector<rtaccel_hit> hits(rays.size());
  s = rtaccel_read_hits(dev, hits.data(), uint32_t(hits.size()));
  expect(s == RTACCEL_OK, "read hits: " + named(s));
  size_t misnumbered = 0;
  for (size_t i = 0; i < hits.size(); ++i) misnumbered += hits[i].number != i;
  expect(misnumbered == 0, "hit i carries number i (" + std::to_string(misnumbered) + " do not)");
  rtaccel_counters c{};
  s = rtaccel_read_counters(dev, &c);
  expect(s == RTACCEL_OK && c.rays_done == rays.size() && c.hits_out == rays.size() && c.rays_in == rays.size() &&
             c.cycles > 0 && c.axi_write_beats > 0,
         "counters: RAYS_DONE " + std::to_string(c.rays_done) + ", HITS_OUT " + std::to_string(c.hits_out) + ", CYCLES " +
             std::to_string(c.cycles));
  {
    std::ofstream h(out + "/hits.bin", std::ios::binary);
    h.write(reinterpret_cast<const char*>(hits.data()), std::streamsize(hits.size() * sizeof(rtaccel_hit)));
    expect(bool(h), out + "/hits.bin written");
  }
  rtaccel_close(dev);

  // The C++ wrapper: a second device, one ray, the same answer as ray 0 of the batch.
  rtaccel::Device d2;
  s = rtaccel::Device::openSim(o, d2);
  expect(s == RTACCEL_OK, "C++ wrapper: open");
  if (s == RTACCEL_OK) {
    std::vector<rtaccel_hit> one;
    bool ok = d2.loadScene(pkg + "/image.bin") == RTACCEL_OK && d2.submit({rays[0]}) == RTACCEL_OK &&
              d2.wait() == RTACCEL_OK && d2.hits(one, 1) == RTACCEL_OK;
    expect(ok && std::memcmp(&one[0], &hits[0], sizeof(rtaccel_hit)) == 0, "C++ wrapper: ray 0 alone gives the same hit " +
                                                                            d2.lastError());
  }
  std::printf("test-librtaccel: %d failures\n", failures);
  return failures ? 1 : 0;
}
