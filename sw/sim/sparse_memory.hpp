// The DDR's contents: a 32-bit byte address space allocated in 1 MiB pages on
// first write (a read of a never-written page returns zeros), so a 4 GiB
// space costs only what a run touches.
#pragma once
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <memory>
#include <vector>

namespace rtaccel::sim {

class SparseMemory {
 public:
  static constexpr uint64_t kSpace = 1ULL << 32;
  static constexpr unsigned kPageBits = 20;
  static constexpr uint64_t kPage = 1ULL << kPageBits;

  SparseMemory() : pages_(kSpace >> kPageBits) {}

  // Callers check `addr + n <= kSpace` (AxiMemory answers DECERR beyond it).
  void read(uint64_t addr, void* dst, uint64_t n) const {
    auto* out = static_cast<uint8_t*>(dst);
    while (n > 0) {
      uint64_t off = addr & (kPage - 1), k = std::min(n, kPage - off);
      const auto& p = pages_[addr >> kPageBits];
      if (p) std::memcpy(out, p.get() + off, k); else std::memset(out, 0, k);
      addr += k; out += k; n -= k;
    }
  }
  void write(uint64_t addr, const void* src, uint64_t n) {
    auto* in = static_cast<const uint8_t*>(src);
    while (n > 0) {
      uint64_t off = addr & (kPage - 1), k = std::min(n, kPage - off);
      std::memcpy(page(addr) + off, in, k);
      addr += k; in += k; n -= k;
    }
  }
  // One 64-byte-aligned line under a byte-enable mask (bit i = byte i), as an AXI W beat.
  void writeLine(uint64_t lineAddr, const uint8_t* src, uint64_t strobes) {
    uint8_t* p = page(lineAddr) + (lineAddr & (kPage - 1));
    if (strobes == ~0ULL) { std::memcpy(p, src, 64); return; }
    for (int i = 0; i < 64; ++i) if ((strobes >> i) & 1) p[i] = src[i];
  }

 private:
  // calloc, not new + memset: a page this large comes zeroed from the kernel, which
  // then maps only the 4 KiB pieces a run touches (memset touched all 256 of them).
  struct Free { void operator()(uint8_t* p) const { std::free(p); } };
  uint8_t* page(uint64_t addr) {
    auto& p = pages_[addr >> kPageBits];
    if (!p) {
      p.reset(static_cast<uint8_t*>(std::calloc(kPage, 1)));
      if (!p) throw std::bad_alloc();
    }
    return p.get();
  }
  std::vector<std::unique_ptr<uint8_t[], Free>> pages_;
};

}  // namespace rtaccel::sim
