// FP32 operations rounded toward -inf (RDN), +inf (RUP) or zero (RTZ), as the
// conservative box kernel needs them (src/main/scala/rtaccel/datapath/BoxKernel.scala,
// RayKernel.scala), without changing the FPU's rounding mode: the exact
// result (or a double plus the sign of its residual) is rounded to nearest,
// then stepped one ulp when that went the wrong way. Bit-exact with FpModel's
// directed modes, zeros and overflow included; checked against the RTL's
// golden hits by nori-accel/tests/golden_check.cpp.
#pragma once
#include <cmath>
#if defined(__AVX512F__)
#include <immintrin.h>
#endif
#include "../../hls/fp32.h"

namespace rtg {

enum class Dir { Down, Up };

// The next float toward -inf / +inf (x not NaN), by the bits: std::nextafter
// is a library call and this runs several times per box test.
inline float next_down(float x) {
  const uint32_t b = rt::bits(x);
  if ((b & 0x7fffffffu) == 0) return rt::from_bits(0x80000001u);  // ±0 -> -min subnormal
  if (b == 0xff800000u) return x;                                    // -inf stays
  return rt::from_bits((b >> 31) ? b + 1 : b - 1);
}
inline float next_up(float x) { return -next_down(-x); }

// Round x + e (e = exact residual, |e| <= half an ulp of the double x, only
// its sign is used) to FP32 in direction `dir`. (float)x rounds to nearest;
// stepping one float ulp fixes it whenever it landed on the wrong side of the
// exact value. Overflow: nearest gives inf, stepped back to FLT_MAX for the
// direction that must stay finite (IEEE directed overflow).
inline float round_dir(double x, double e, Dir dir) {
  float f = static_cast<float>(x);
  const double fd = static_cast<double>(f);
  if (dir == Dir::Down) {
    if (fd > x || (fd == x && e < 0.0)) f = next_down(f);
  } else {
    if (fd < x || (fd == x && e > 0.0)) f = next_up(f);
  }
  return f;
}

// a - b rounded in `dir`. In double the difference may round (exponents far
// apart), so TwoSum gives its exact residual. An exact zero difference of
// nonzero operands is -0 in RDN and +0 otherwise (IEEE 754 6.3, FpModel.add);
// (-0) - (+0) stays -0 in every mode.
inline float sub_dir_portable(float a, float b, Dir dir) {
  const double x = static_cast<double>(a), y = -static_cast<double>(b);
  const double s = x + y;
  if (s == 0.0) {
    const bool sa = rt::sign_bit(a), sb = !rt::sign_bit(b);
    const bool neg = sa == sb ? sa : dir == Dir::Down;
    return neg ? -0.0f : 0.0f;
  }
  if (std::isinf(x) || std::isinf(y)) return static_cast<float>(s);  // exact (or NaN for inf - inf)
  const double bb = s - x;
  const double e = (x - (s - bb)) + (y - bb);
  return round_dir(s, e, dir);
}

// a * b rounded in `dir`: the product of two floats is exact in double
// (48 significant bits, exponent range far inside double's).
inline float mul_dir_portable(float a, float b, Dir dir) {
  const double p = static_cast<double>(a) * static_cast<double>(b);
  if (p == 0.0 || std::isinf(p) || std::isnan(p)) return static_cast<float>(p);
  return round_dir(p, 0.0, dir);
}

// 1 / m for m = |d| > 0 finite, rounded in `dir` (RTZ = Down for a positive
// result). f = the float nearest the double quotient is the nearest float to
// 1/m or one of its neighbours' correct choice; f * m is exact in double
// (24 x 24 bits), so comparing it with 1 says on which side of 1/m f lies.
inline float recip_dir_portable(float m, Dir dir) {
  if (rt::is_zero(m)) return rt::kInf;  // every mode: 1/0 = inf
  if (std::isinf(m)) return 0.0f;       // exact
  const double md = static_cast<double>(m);
  float f = static_cast<float>(1.0 / md);
  const double p = static_cast<double>(f) * md;  // inf when f overflowed
  if (dir == Dir::Down && p > 1.0) f = next_down(f);
  if (dir == Dir::Up && p < 1.0) f = next_up(f);
  return f;
}

#if defined(__AVX512F__)
// With AVX-512 each directed operation is one instruction with its rounding
// mode embedded (IEEE 754 exactly, zero signs included; MXCSR's FTZ/DAZ are
// off by default and nothing here sets them). tests/directed_check.cpp
// checks both forms against the FPU in fesetround modes.
inline __m128 ss(float x) { return _mm_set_ss(x); }
inline float sub_dir(float a, float b, Dir dir) {
  return _mm_cvtss_f32(dir == Dir::Down ? _mm_sub_round_ss(ss(a), ss(b), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)
                                        : _mm_sub_round_ss(ss(a), ss(b), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
}
inline float mul_dir(float a, float b, Dir dir) {
  return _mm_cvtss_f32(dir == Dir::Down ? _mm_mul_round_ss(ss(a), ss(b), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)
                                        : _mm_mul_round_ss(ss(a), ss(b), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
}
inline float recip_dir(float m, Dir dir) {
  return _mm_cvtss_f32(dir == Dir::Down ? _mm_div_round_ss(ss(1.0f), ss(m), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)
                                        : _mm_div_round_ss(ss(1.0f), ss(m), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC));
}
#else
inline float sub_dir(float a, float b, Dir dir) { return sub_dir_portable(a, b, dir); }
inline float mul_dir(float a, float b, Dir dir) { return mul_dir_portable(a, b, dir); }
inline float recip_dir(float m, Dir dir) { return recip_dir_portable(m, dir); }
#endif

}  // namespace rtg
