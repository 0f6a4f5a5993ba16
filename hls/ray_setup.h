// Per-ray quantities, computed once per ray before any box or triangle test:
// the reciprocal direction (slab test), the error bit, and the watertight
// shear constants. See docs/kernels.md, "Per-ray setup".
#pragma once
#include "fp32.h"

namespace rt {

struct Ray {
  float o[3];
  float d[3];
  float rcp[3];  // rcp[i] = 1/d[i], IEEE division, RNE (±inf for d[i] = ±0)
  float tmin;
  float tmax;
};

// Watertight shear: kz = axis of largest |d|, (kx, ky) the next two axes in
// cyclic order, swapped when d[kz] < 0 so the winding is kept.
struct RayShear {
  int kx, ky, kz;
  float sx, sy, sz;  // sz = rcp[kz]; sx = d[kx] * sz; sy = d[ky] * sz
};

// Error bit: NaN or ±inf in o or d, NaN tmin or tmax, or d = (±0, ±0, ±0).
// Such a ray is a defined miss in every kernel.
inline bool ray_error(const float o[3], const float d[3], float tmin, float tmax) {
  bool bad = is_nan(tmin) || is_nan(tmax);
  bool all_zero = true;
  for (int i = 0; i < 3; ++i) {
    bad = bad || is_nonfinite(o[i]) || is_nonfinite(d[i]);
    all_zero = all_zero && is_zero(d[i]);
  }
  return bad || all_zero;
}

inline Ray make_ray(const float o[3], const float d[3], float tmin, float tmax) {
  Ray r;
  for (int i = 0; i < 3; ++i) {
    r.o[i] = o[i];
    r.d[i] = d[i];
    r.rcp[i] = 1.0f / d[i];
  }
  r.tmin = tmin;
  r.tmax = tmax;
  return r;
}

// |d| compared on magnitude bits (exact). Ties go to the lowest axis index
// (strict >), so the choice is deterministic.
inline RayShear make_shear(const Ray& r) {
  int kz = 0;
  uint32_t best = bits(r.d[0]) & 0x7fffffffu;
  for (int i = 1; i < 3; ++i) {
    const uint32_t m = bits(r.d[i]) & 0x7fffffffu;
    if (m > best) { best = m; kz = i; }
  }
  RayShear s;
  s.kz = kz;
  s.kx = (kz + 1) % 3;
  s.ky = (kz + 2) % 3;
  if (sign_bit(r.d[kz])) { const int t = s.kx; s.kx = s.ky; s.ky = t; }
  s.sz = r.rcp[kz];
  s.sx = r.d[s.kx] * s.sz;
  s.sy = r.d[s.ky] * s.sz;
  return s;
}

}  // namespace rt
