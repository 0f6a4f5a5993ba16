#include "case_gen.h"

#include <cmath>

#include "fp32.h"

namespace rt {

namespace {

using V3 = double[3];

float f(double x) { return static_cast<float>(x); }  // RNE to FP32

void to_f(const V3 v, float out[3]) { for (int i = 0; i < 3; ++i) out[i] = f(v[i]); }

// A point with each coordinate at scale `s` (sign random), exponents mixed.
void random_point(Rng& rng, double s, V3 out) {
  for (int i = 0; i < 3; ++i) out[i] = rng.sign() * s * rng.uniform();
}

// Common ray end: tmin/tmax mostly [0, inf), sometimes a finite window.
void random_interval(Rng& rng, float& tmin, float& tmax) {
  tmin = 0.0f;
  tmax = kInf;
  if (rng.chance(0.2)) tmin = f(rng.uniform(-1.0, 0.5));
  if (rng.chance(0.2)) tmax = f(rng.uniform(0.5, 4.0));
}

// d = target - origin in FP32, rescaled by a power of two (exact) so the
// direction exponent varies while the ray still passes the target at some t.
void aim(Rng& rng, const float o[3], const float target[3], float d[3]) {
  const float scale = f(rng.pow2(-20, 20));
  for (int i = 0; i < 3; ++i) d[i] = (target[i] - o[i]) * scale;
}

// Replaces one input by NaN, +inf or -inf (error-bit family).
template <typename Case>
void poison(Rng& rng, Case& c) {
  const float bad[3] = {from_bits(kCanonicalNaN), kInf, -kInf};
  const float v = bad[rng.below(3)];
  switch (rng.below(4)) {
    case 0: c.o[rng.below(3)] = v; break;
    case 1: c.d[rng.below(3)] = v; break;
    case 2: c.tmin = from_bits(kCanonicalNaN); break;
    default: c.tmax = from_bits(kCanonicalNaN); break;
  }
}

}  // namespace

BoxCase random_box_case(Rng& rng) {
  static const char* kFamilies[] = {"generic", "axis", "on_plane", "grazing", "offset",
                                    "tiny", "subnormal_d", "nonfinite"};
  const int fam = rng.below(8);
  BoxCase c;
  c.family = kFamilies[fam];
  const double s = fam == 5 ? rng.pow2(-30, -18) : rng.pow2(-12, 12);
  const double offset = fam == 4 ? (rng.chance(0.5) ? 1e4 : 1e6) : 0.0;
  V3 center, half, origin;
  random_point(rng, s * 4, center);
  for (int i = 0; i < 3; ++i) {
    center[i] += offset;
    half[i] = s * rng.uniform(0.0, 1.0) * (rng.chance(0.1) ? 0.0 : 1.0);
    c.bmin[i] = f(center[i] - half[i]);
    c.bmax[i] = f(center[i] + half[i]);
  }
  random_point(rng, s * 8, origin);
  for (int i = 0; i < 3; ++i) origin[i] += center[i];
  to_f(origin, c.o);
  // Target: a box point pushed a little outside or inside; grazing targets a
  // face, edge or corner exactly.
  float target[3];
  for (int i = 0; i < 3; ++i) {
    const double a = rng.uniform(-0.2, 1.2);
    target[i] = f(c.bmin[i] + a * (double(c.bmax[i]) - c.bmin[i]));
    if (fam == 3 && rng.chance(0.6)) target[i] = rng.chance(0.5) ? c.bmin[i] : c.bmax[i];
  }
  aim(rng, c.o, target, c.d);
  random_interval(rng, c.tmin, c.tmax);
  if (fam == 1) {  // one or two zero components, either sign of zero
    const int n = 1 + rng.below(2);
    for (int k = 0; k < n; ++k) c.d[rng.below(3)] = rng.chance(0.5) ? 0.0f : -0.0f;
  }
  if (fam == 2) {  // origin exactly on one or more slab planes
    for (int i = 0; i < 3; ++i)
      if (rng.chance(0.5)) c.o[i] = rng.chance(0.5) ? c.bmin[i] : c.bmax[i];
    if (rng.chance(0.3)) c.d[rng.below(3)] = rng.chance(0.5) ? 0.0f : -0.0f;
  }
  if (fam == 6) {  // subnormal or tiny components: 1/d overflows to inf
    for (int i = 0; i < 3; ++i)
      if (rng.chance(0.5)) c.d[i] = f(rng.sign() * rng.pow2(-149, -120));
    if (rng.chance(0.5)) c.o[rng.below(3)] = c.bmin[rng.below(3)];
  }
  if (fam == 7) poison(rng, c);
  return c;
}

TriCase random_tri_case(Rng& rng) {
  static const char* kFamilies[] = {"generic", "edge", "vertex", "grazing", "offset", "tiny",
                                    "needle", "zero_area", "nonfinite", "mixed_exp"};
  const int fam = rng.below(10);
  TriCase c;
  c.family = kFamilies[fam];
  const double s = fam == 5 ? 1e-6 * rng.uniform(0.5, 2.0) : rng.pow2(-10, 10);
  const double offset = fam == 4 ? (rng.chance(0.5) ? 1e4 : 1e6) : 0.0;
  V3 center, v0, v1, v2, origin;
  random_point(rng, fam == 5 ? 1.0 : s * 4, center);
  for (int i = 0; i < 3; ++i) center[i] += offset;
  random_point(rng, s, v0);
  random_point(rng, s, v1);
  random_point(rng, s, v2);
  if (fam == 9)  // one coordinate axis at a very different exponent
    for (V3* v : {&v0, &v1, &v2}) (*v)[rng.below(3)] *= rng.pow2(-20, 20);
  if (fam == 6) {  // needle: p2 almost on the line p0-p1
    const double a = rng.uniform(-0.5, 1.5), w = rng.pow2(-40, -16);
    for (int i = 0; i < 3; ++i) v2[i] = v0[i] + a * (v1[i] - v0[i]) + w * s * rng.uniform(-1, 1);
  }
  for (int i = 0; i < 3; ++i) {
    c.p0[i] = f(center[i] + v0[i]);
    c.p1[i] = f(center[i] + v1[i]);
    c.p2[i] = f(center[i] + v2[i]);
  }
  if (fam == 7) {  // coincident pair, all three, or exactly collinear (p2 = p0 + 2 (p1 - p0))
    const int k = rng.below(5);
    for (int i = 0; i < 3; ++i) {
      if (k == 0) c.p1[i] = c.p0[i];
      if (k == 1) c.p2[i] = c.p1[i];
      if (k == 2) c.p2[i] = c.p0[i];
      if (k == 3) c.p1[i] = c.p2[i] = c.p0[i];
      if (k == 4) c.p2[i] = c.p0[i] + 2.0f * (c.p1[i] - c.p0[i]);
    }
    if (k == 4) c.family = "collinear";
  }
  random_point(rng, fam == 5 ? 4e-6 : s * 8, origin);
  for (int i = 0; i < 3; ++i) origin[i] += center[i];
  to_f(origin, c.o);
  // Target: barycentric (b1, b2); edge/vertex families put it exactly on an
  // edge or vertex of the FP32 triangle (edge points rounded to FP32).
  double b1 = rng.uniform(-0.1, 1.1), b2 = rng.uniform(-0.1, 1.1);
  if (fam == 1) {
    const int e = rng.below(3);
    b1 = rng.uniform();
    b2 = e == 0 ? 0.0 : e == 1 ? 1.0 - b1 : b2;
    if (e == 2) { b2 = b1; b1 = 0.0; }
  }
  if (fam == 2) {
    const int k = rng.below(3);
    b1 = k == 1; b2 = k == 2;
  }
  float target[3];
  for (int i = 0; i < 3; ++i)
    target[i] = f(c.p0[i] + b1 * (double(c.p1[i]) - c.p0[i]) + b2 * (double(c.p2[i]) - c.p0[i]));
  if (fam == 3) {  // grazing: origin in the plane, direction along the plane
    const double a0 = rng.uniform(-2, 2), a1 = rng.uniform(-2, 2);
    for (int i = 0; i < 3; ++i)
      c.o[i] = f(c.p0[i] + a0 * (double(c.p1[i]) - c.p0[i]) + a1 * (double(c.p2[i]) - c.p0[i]));
  }
  aim(rng, c.o, target, c.d);
  random_interval(rng, c.tmin, c.tmax);
  if (fam == 8) poison(rng, c);
  return c;
}

}  // namespace rt
