// FP32 bit-level helpers shared by the kernels and the test benches.
// Everything here is exact (no rounding): classification, the total-order
// min/max used by the slab test, and hex formatting of bit patterns.
#pragma once
#include <cstdint>
#include <cstring>

namespace rt {

// Bit casts. HLS tools synthesize the union form (pure wiring); g++ uses
// memcpy, the portable C++ way. Both give the same bits.
#ifdef __SYNTHESIS__
inline uint32_t bits(float x) { union { float f; uint32_t u; } c; c.f = x; return c.u; }
inline float from_bits(uint32_t b) { union { float f; uint32_t u; } c; c.u = b; return c.f; }
#else
inline uint32_t bits(float x) { uint32_t b; std::memcpy(&b, &x, 4); return b; }
inline float from_bits(uint32_t b) { float x; std::memcpy(&x, &b, 4); return x; }
#endif

inline bool is_nan(float x) { return (bits(x) & 0x7fffffffu) > 0x7f800000u; }
inline bool is_nonfinite(float x) { return (bits(x) & 0x7f800000u) == 0x7f800000u; }
inline bool is_zero(float x) { return (bits(x) & 0x7fffffffu) == 0u; }
inline bool sign_bit(float x) { return (bits(x) >> 31) != 0u; }

constexpr float kInf = __builtin_huge_valf();
constexpr uint32_t kCanonicalNaN = 0x7fc00000u;  // same as the Chisel FP units

// Total-order key of a non-NaN value with -0 below +0 (IEEE 754-2019
// minimumNumber/maximumNumber order).
inline int64_t order_key(float x) {
  const uint32_t b = bits(x);
  const int64_t mag = b & 0x7fffffffu;
  return (b >> 31) ? -mag - 1 : mag;
}

// maximumNumber: a NaN operand loses (the other is returned), -0 < +0.
// Written out explicitly instead of std::max/fmax so the NaN and signed-zero
// behaviour is the one documented in docs/kernels.md, not a library quirk.
inline float max_num(float a, float b) {
  if (is_nan(a)) return is_nan(b) ? from_bits(kCanonicalNaN) : b;
  if (is_nan(b)) return a;
  return order_key(a) >= order_key(b) ? a : b;
}

// minimumNumber: a NaN operand loses, -0 < +0.
inline float min_num(float a, float b) {
  if (is_nan(a)) return is_nan(b) ? from_bits(kCanonicalNaN) : b;
  if (is_nan(b)) return a;
  return order_key(a) <= order_key(b) ? a : b;
}

// Bits for the vector files: every NaN is written as the canonical NaN, so the
// files do not depend on the host's NaN payload propagation.
inline uint32_t file_bits(float x) { return is_nan(x) ? kCanonicalNaN : bits(x); }

}  // namespace rt
