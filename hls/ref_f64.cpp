#include "ref_f64.h"

#include <cfloat>
#include <cmath>

#include "ray_setup.h"

namespace rt {

double box_error_bound(double t, double diff) {
  // u = 2^-24 (FP32 unit roundoff). gamma(3) = 3u / (1 - 3u) covers the three
  // roundings of normal results; 2^-50 covers the f64 reference's own
  // rounding. Subnormal results (1/d for |d| > 2^126, or a tiny product) add
  // an absolute error of at most half an ulp of 2^-149 each, amplified by at
  // most |diff| when the subnormal is the reciprocal.
  const double u = 0x1.0p-24;
  const double gamma3 = 3 * u / (1 - 3 * u);
  return (gamma3 + 0x1.0p-50) * std::fabs(t) + (std::fabs(diff) + 1.0) * 0x1.0p-149;
}

BoxRef box_ref_f64(const BoxCase& c) {
  BoxRef r{false, false, nullptr};
  if (ray_error(c.o, c.d, c.tmin, c.tmax)) return r;
  double near = -INFINITY, far = INFINITY, near_up = -INFINITY, far_dn = INFINITY;
  const char* fragile = nullptr;
  for (int i = 0; i < 3; ++i) {
    const double lo_b = c.bmin[i], hi_b = c.bmax[i], o = c.o[i], d = c.d[i];
    if (!(lo_b <= hi_b)) return r;
    if (d == 0.0) {
      if (o < lo_b || o > hi_b) return r;
      continue;
    }
    const double diff_lo = lo_b - o, diff_hi = hi_b - o;
    double t1 = diff_lo / d, t2 = diff_hi / d;
    double e1 = box_error_bound(t1, diff_lo), e2 = box_error_bound(t2, diff_hi);
    if (d < 0) { std::swap(t1, t2); std::swap(e1, e2); }
    near = std::fmax(near, t1);
    far = std::fmin(far, t2);
    near_up = std::fmax(near_up, t1 + e1);
    far_dn = std::fmin(far_dn, t2 - e2);
    // 1/d overflowed to inf: the FP32 plane distances become +-inf (or NaN,
    // ignored, when the origin is on the plane). That is harmless unless the
    // origin is strictly outside the slab, where a finite entry distance
    // becomes inf.
    const bool outside_slab = o < lo_b || o > hi_b;
    if (std::isinf(1.0f / c.d[i]) && outside_slab) fragile = "rcp_overflow";
    else if (std::fabs(diff_lo) > FLT_MAX || std::fabs(diff_hi) > FLT_MAX) fragile = fragile ? fragile : "diff_overflow";
  }
  const double tmin = c.tmin, tmax = c.tmax;
  r.hit = near <= far && tmin <= far && near <= tmax;
  const bool margin_ok = near_up <= far_dn && tmin <= far_dn && near_up <= tmax;
  r.robust = r.hit && margin_ok && fragile == nullptr;
  r.fragile = r.hit && !r.robust ? (fragile ? fragile : "margin") : nullptr;
  return r;
}

bool tri_ref_f64(const TriCase& c) {
  if (ray_error(c.o, c.d, c.tmin, c.tmax)) return false;
  double e1[3], e2[3], tv[3], d[3];
  for (int i = 0; i < 3; ++i) {
    e1[i] = double(c.p1[i]) - c.p0[i];
    e2[i] = double(c.p2[i]) - c.p0[i];
    tv[i] = double(c.o[i]) - c.p0[i];
    d[i] = c.d[i];
  }
  auto cross = [](const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  double p[3], q[3];
  cross(d, e2, p);
  const double det = dot(e1, p);
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double u = dot(tv, p) / det;
  cross(tv, e1, q);
  const double v = dot(d, q) / det;
  const double t = dot(e2, q) / det;
  return u >= 0 && v >= 0 && u + v <= 1 && t >= c.tmin && t <= c.tmax;
}

}  // namespace rt
