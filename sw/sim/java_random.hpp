// java.util.Random's generator, bit for bit: the Scala memory models draw
// their latencies, readies and reordering choices from scala.util.Random(seed),
// which is this LCG, so a C++ model making the same calls in the same order
// makes the same choices.
#pragma once
#include <cstdint>

namespace rtaccel::sim {

class JavaRandom {
 public:
  explicit JavaRandom(int64_t seed) : seed_((uint64_t(seed) ^ kMult) & kMask) {}

  // Random.nextDouble(): 53 random bits in [0, 1).
  double nextDouble() { return double((int64_t(next(26)) << 27) + next(27)) * 0x1.0p-53; }

  // Random.nextInt(bound), bound >= 1: the same rejection loop as the JDK.
  int32_t nextInt(int32_t bound) {
    int32_t r = next(31);
    int32_t m = bound - 1;
    if ((bound & m) == 0) return int32_t((int64_t(bound) * int64_t(r)) >> 31);
    for (int32_t u = r; int32_t(uint32_t(u) - uint32_t(r = u % bound) + uint32_t(m)) < 0; u = next(31)) {
    }
    return r;
  }

 private:
  static constexpr uint64_t kMult = 0x5DEECE66DULL;
  static constexpr uint64_t kMask = (1ULL << 48) - 1;
  int32_t next(int bits) {
    seed_ = (seed_ * kMult + 0xBULL) & kMask;
    return int32_t(int64_t(seed_) >> (48 - bits));
  }
  uint64_t seed_;
};

}  // namespace rtaccel::sim
