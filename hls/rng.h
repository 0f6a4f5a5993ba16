// Seeded random source of the test benches: xoshiro256** (Blackman & Vigna)
// seeded through splitmix64 from one 64-bit seed. Same seed, same vectors, on
// every host (no <random> distributions, whose output is library-specific).
#pragma once
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace rt {

class Rng {
 public:
  explicit Rng(uint64_t seed) {
    for (auto& w : s_) {
      seed += 0x9e3779b97f4a7c15ull;
      uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
      w = z ^ (z >> 31);
    }
  }
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0]; s_[3] ^= s_[1]; s_[1] ^= s_[2]; s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  int below(int n) { return static_cast<int>(uniform() * n); }
  bool chance(double p) { return uniform() < p; }
  // 2^k with k uniform in [lo, hi]: mixes exponents.
  double pow2(int lo, int hi) { return std::ldexp(1.0, lo + below(hi - lo + 1)); }
  double sign() { return chance(0.5) ? -1.0 : 1.0; }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

// The seed: RT_SEED from the environment (decimal or 0x-hex), else the
// documented default. Test benches print it.
inline uint64_t test_seed(const char* env_value, uint64_t fallback) {
  if (env_value == nullptr || *env_value == '\0') return fallback;
  return std::strtoull(env_value, nullptr, 0);
}

}  // namespace rt
