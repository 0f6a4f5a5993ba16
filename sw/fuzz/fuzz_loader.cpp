// libFuzzer target over librtaccel's scene loader and the scene package's ray
// reader (make fuzz, docs/faults.md "Fuzzing"). The first input byte picks the
// path, the rest is the file:
//   0: a memory image through rtaccel_load_scene (in memory);
//   1: a memory image through rtaccel_load_scene_file (a file, as a package's image.bin);
//   2: a package's rays.csv through readRaysCsv (sw/sim/rays_csv.cpp), then, with a
//      scene loaded, the rays read submitted as a batch and their hits read back.
// The device is a register-level stand-in (no RTL: the fuzzer needs thousands of
// runs a second): LOAD_SCENE applies the hardware's header checks
// (SceneLoader.scala, in the same order) to the image in its memory and answers
// SCENE_READY or SCENE_ERROR with the code; START ends the batch at once with
// every hit written. A crash, a sanitizer report, or a call that returns an
// undocumented status (checked below) is a finding.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>
#include <vector>

#include "backend.h"
#include "rays_csv.hpp"
#include "rtaccel.h"
#include "rtaccel_regs.h"

namespace {

// The stand-in's hardware: 4-wide nodes (layout 4, 128-byte nodes), stack depth 24, 512-bit m_axi.
constexpr uint32_t Layout = 4, NodeBytes = 128, TriBytes = 64, StackDepth = 24, ImageVersion = 3;
constexpr uint64_t BufBase = 0x10000000ull, BufSize = 1u << 16;  // 64 KiB: Cornell's image is 2.6 KB

struct Fake {
  uint32_t regs[1024] = {};
  std::vector<uint8_t> mem = std::vector<uint8_t>(BufSize);
};

uint32_t word(const Fake& f, uint64_t addr) {
  if (addr < BufBase || addr + 4 > BufBase + BufSize) return 0;  // outside the buffer: the memory reads zeros
  uint32_t v;
  std::memcpy(&v, &f.mem[addr - BufBase], 4);
  return v;
}

uint32_t& reg(Fake& f, uint32_t off) { return f.regs[(off & 0xfff) >> 2]; }

// SceneLoader's checks on the 64-byte header at SCENE_BASE, in its order.
uint32_t sceneCode(const Fake& f, uint64_t base) {
  auto w = [&](int k) { return word(f, base + 4 * k); };
  if (base % 64 != 0) return RTACCEL_SCENE_MISALIGNED;
  if (w(0) != 0x43435452u || w(1) != 0x004c4543u) return RTACCEL_SCENE_BAD_MAGIC;  // "RTACCEL\0"
  if (w(2) != ImageVersion) return RTACCEL_SCENE_BAD_VERSION;
  if (w(11) != Layout) return RTACCEL_SCENE_LAYOUT;
  if (w(7) != NodeBytes || w(8) != TriBytes) return RTACCEL_SCENE_RECORD_SIZE;
  if (w(5) % 64 != 0 || w(6) % 64 != 0) return RTACCEL_SCENE_MISALIGNED;
  if (w(10) > StackDepth) return RTACCEL_SCENE_STACK_BOUND;
  return RTACCEL_SCENE_OK;
}

rtaccel_status regRead(void* ctx, uint32_t off, uint32_t* v, char*, size_t) {
  Fake& f = *static_cast<Fake*>(ctx);
  switch (off) {
    case RTACCEL_ID_OFFSET: *v = RTACCEL_ID_VALUE; break;
    case RTACCEL_VERSION_OFFSET: *v = RTACCEL_VERSION_VALUE; break;
    case RTACCEL_CONFIG_LAYOUT_OFFSET: *v = Layout; break;
    case RTACCEL_CONFIG_AXI_DATA_BITS_OFFSET: *v = 512; break;
    default: *v = reg(f, off);
  }
  return RTACCEL_OK;
}

rtaccel_status regWrite(void* ctx, uint32_t off, uint32_t v, char*, size_t) {
  Fake& f = *static_cast<Fake*>(ctx);
  uint32_t& status = reg(f, RTACCEL_STATUS_OFFSET);
  if (off == RTACCEL_IRQ_STATUS_OFFSET) { reg(f, off) &= ~v; return RTACCEL_OK; }
  if (off != RTACCEL_CTRL_OFFSET) { reg(f, off) = v; return RTACCEL_OK; }
  if (v & RTACCEL_CTRL_SOFT_RESET_MASK) status = 0;
  if (v & RTACCEL_CTRL_LOAD_SCENE_MASK) {
    uint32_t code = sceneCode(f, reg(f, RTACCEL_SCENE_BASE_OFFSET));
    reg(f, RTACCEL_SCENE_ERROR_CODE_OFFSET) = code;
    status = code ? RTACCEL_STATUS_SCENE_ERROR_MASK : RTACCEL_STATUS_SCENE_READY_MASK;
    reg(f, RTACCEL_IRQ_STATUS_OFFSET) |= RTACCEL_IRQ_STATUS_SCENE_MASK;
  }
  if ((v & RTACCEL_CTRL_START_MASK) && (status & RTACCEL_STATUS_SCENE_READY_MASK)) {
    uint32_t n = reg(f, RTACCEL_RAY_COUNT_OFFSET);
    uint64_t hits = reg(f, RTACCEL_HIT_BASE_OFFSET);
    for (uint32_t i = 0; i < n; i++) {  // a miss for every ray, numbered as the hardware numbers them
      uint64_t a = hits + 32ull * i;
      if (a >= BufBase && a + 32 <= BufBase + BufSize) {
        std::memset(&f.mem[a - BufBase], 0, 32);
        std::memcpy(&f.mem[a - BufBase], &i, 4);
      }
    }
    reg(f, RTACCEL_RAYS_DONE_OFFSET) = reg(f, RTACCEL_RAYS_ISSUED_OFFSET) = n;
    status = (status & ~RTACCEL_STATUS_BUSY_MASK) | RTACCEL_STATUS_DONE_MASK;
    reg(f, RTACCEL_IRQ_STATUS_OFFSET) |= RTACCEL_IRQ_STATUS_DONE_MASK;
  }
  return RTACCEL_OK;
}

rtaccel_status memAccess(Fake& f, uint64_t addr, size_t n, char* err, size_t errn) {
  if (addr < BufBase || addr + n > BufBase + BufSize || addr + n < addr) {
    std::snprintf(err, errn, "fuzz: [0x%llx, +%zu) outside the device buffer", (unsigned long long)addr, n);
    // librtaccel must never ask for this: its own bounds come first.
    std::fprintf(stderr, "%s\n", err);
    std::abort();
  }
  (void)f;
  return RTACCEL_OK;
}
rtaccel_status memWrite(void* ctx, uint64_t addr, const void* src, size_t n, char* err, size_t errn) {
  Fake& f = *static_cast<Fake*>(ctx);
  memAccess(f, addr, n, err, errn);
  std::memcpy(&f.mem[addr - BufBase], src, n);
  return RTACCEL_OK;
}
rtaccel_status memRead(void* ctx, uint64_t addr, void* dst, size_t n, char* err, size_t errn) {
  Fake& f = *static_cast<Fake*>(ctx);
  memAccess(f, addr, n, err, errn);
  std::memcpy(dst, &f.mem[addr - BufBase], n);
  return RTACCEL_OK;
}
rtaccel_status waitIrq(void* ctx, uint32_t, char* err, size_t errn) {
  Fake& f = *static_cast<Fake*>(ctx);
  if (reg(f, RTACCEL_IRQ_STATUS_OFFSET) & reg(f, RTACCEL_IRQ_ENABLE_OFFSET)) return RTACCEL_OK;
  std::snprintf(err, errn, "fuzz: no interrupt");
  return RTACCEL_ERR_TIMEOUT;
}
void closeFake(void* ctx) { delete static_cast<Fake*>(ctx); }

const rtaccel_backend fakeBackend = {"fuzz", regRead, regWrite, memWrite, memRead, waitIrq, nullptr, nullptr,
                                     nullptr, nullptr, closeFake, nullptr, nullptr};

// The statuses each call may return (rtaccel.h); anything else is a finding.
bool documented(rtaccel_status s) { return s <= RTACCEL_OK && s >= RTACCEL_ERR_STATE; }
void check(rtaccel_status s, const char* call) {
  if (!documented(s)) {
    std::fprintf(stderr, "fuzz: %s returned %d, not an rtaccel_status\n", call, (int)s);
    std::abort();
  }
}

std::string tempFile(const uint8_t* data, size_t n) {
  static std::string path = [] {
    char p[] = "/tmp/rtaccel-fuzz-XXXXXX";
    int fd = mkstemp(p);
    if (fd < 0) std::abort();
    close(fd);
    return std::string(p);
  }();
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || (n && std::fwrite(data, 1, n, f) != n)) std::abort();
  std::fclose(f);
  return path;
}

// A valid header for the stand-in, so path 2 can submit: one node, no triangles.
std::vector<uint8_t> tinyScene() {
  std::vector<uint8_t> img(64 + NodeBytes);
  uint32_t w[16] = {0x43435452u, 0x004c4543u, ImageVersion, 1, 0, 64, 64 + NodeBytes, NodeBytes, TriBytes, 0, 1, Layout};
  std::memcpy(img.data(), w, sizeof w);
  return img;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t mode = data[0] % 3;
  data++, size--;
  rtaccel_dev* dev = nullptr;
  if (rtaccel_attach(&fakeBackend, new Fake, BufBase, BufSize, &dev) != RTACCEL_OK) std::abort();
  switch (mode) {
    case 0: check(rtaccel_load_scene(dev, data, size), "rtaccel_load_scene"); break;
    case 1: check(rtaccel_load_scene_file(dev, tempFile(data, size).c_str()), "rtaccel_load_scene_file"); break;
    case 2: {
      std::vector<rtaccel_ray> rays;
      std::string err;
      bool ok = rtaccel::sim::readRaysCsv(tempFile(data, size), 64, rays, err);
      if (!ok && err.empty()) { std::fprintf(stderr, "fuzz: readRaysCsv failed without a message\n"); std::abort(); }
      if (ok && !rays.empty()) {
        std::vector<uint8_t> img = tinyScene();
        check(rtaccel_load_scene(dev, img.data(), img.size()), "rtaccel_load_scene");
        rtaccel_status s = rtaccel_submit(dev, rays.data(), (uint32_t)rays.size());
        check(s, "rtaccel_submit");
        if (s == RTACCEL_OK) {
          check(rtaccel_wait(dev, 1), "rtaccel_wait");
          std::vector<rtaccel_hit> hits(rays.size());
          check(rtaccel_read_hits(dev, hits.data(), (uint32_t)hits.size()), "rtaccel_read_hits");
          for (size_t i = 0; i < hits.size(); i++)
            if (hits[i].number != i) { std::fprintf(stderr, "fuzz: hit %zu numbered %u\n", i, hits[i].number); std::abort(); }
        }
      }
      break;
    }
  }
  rtaccel_close(dev);
  return 0;
}
