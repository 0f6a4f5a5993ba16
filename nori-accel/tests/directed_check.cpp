// The directed-rounding operations of golden/directed.h against the FPU
// itself in fesetround(FE_DOWNWARD / FE_UPWARD) mode, on special values
// (zeros, subnormals, FLT_MAX, infinities, near-ties) and on seeded random
// bit patterns: the portable double-based form, and the AVX-512 form when
// compiled in. Any difference fails with the operands.
#include <cfenv>
#include <cfloat>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "../golden/directed.h"


namespace {
uint64_t rng_state = 0x5eed2026u;  // printed below
uint32_t next_u32() {
  rng_state ^= rng_state << 13; rng_state ^= rng_state >> 7; rng_state ^= rng_state << 17;
  return static_cast<uint32_t>(rng_state >> 11);
}
// The FPU's answer in mode `dir` (volatile keeps the compiler from folding
// the operation at compile time in the default mode).
float fpu(int op, float a, float b, rtg::Dir dir) {
  std::fesetround(dir == rtg::Dir::Down ? FE_DOWNWARD : FE_UPWARD);
  volatile float x = a, y = b;
  volatile float r = op == 0 ? x - y : op == 1 ? x * y : 1.0f / y;
  std::fesetround(FE_TONEAREST);
  return r;
}
}  // namespace

int main() {
  std::printf("directed_check: seed %#llx\n", static_cast<unsigned long long>(rng_state));
  std::vector<float> special = {0.0f, -0.0f, 1.0f, -1.0f, FLT_MIN, -FLT_MIN, FLT_MAX, -FLT_MAX, FLT_TRUE_MIN, -FLT_TRUE_MIN,
                                rt::kInf, -rt::kInf, 3.0f, 1e-30f, 1e30f, 0.1f, 1.0f + FLT_EPSILON, 2.9e-39f, 3.0e38f, 1e-40f};
  std::vector<std::pair<float, float>> cases;
  for (float a : special) for (float b : special) cases.push_back({a, b});
  for (int i = 0; i < 2000000; ++i) {
    float a = rt::from_bits(next_u32()), b = rt::from_bits(next_u32());
    if (i % 2) b = a * (1.0f + (next_u32() % 64) * FLT_EPSILON);  // close operands: cancellation
    if (std::isnan(a) || std::isnan(b)) continue;
    cases.push_back({a, b});
  }
  long bad = 0, n = 0;
  for (auto [a, b] : cases) {
    for (rtg::Dir dir : {rtg::Dir::Down, rtg::Dir::Up}) {
      const float want[3] = {fpu(0, a, b, dir), fpu(1, a, b, dir), fpu(2, 0, std::fabs(b), dir)};
      const float got_p[3] = {rtg::sub_dir_portable(a, b, dir), rtg::mul_dir_portable(a, b, dir), rtg::recip_dir_portable(std::fabs(b), dir)};
      const float got_f[3] = {rtg::sub_dir(a, b, dir), rtg::mul_dir(a, b, dir), rtg::recip_dir(std::fabs(b), dir)};
      for (int op = 0; op < 3; ++op) {
        if (std::isnan(want[op])) continue;  // 0 * inf, inf - inf: never reached by the box kernel
        ++n;
        if (rt::bits(got_p[op]) != rt::bits(want[op]) || rt::bits(got_f[op]) != rt::bits(want[op])) {
          if (++bad <= 10)
            std::printf("directed_check: op %d %s a=%a b=%a: FPU %a, portable %a, fast %a\n", op, dir == rtg::Dir::Down ? "down" : "up",
                        a, b, want[op], got_p[op], got_f[op]);
        }
      }
    }
  }
  std::printf("directed_check: %ld operations, %ld differ from the FPU (%s form%s)\n", n, bad,
#if defined(__AVX512F__)
              "AVX-512 and portable", "s"
#else
              "portable", ""
#endif
  );
  return bad == 0 ? 0 : 1;
}
