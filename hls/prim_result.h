// Output of both triangle kernels.
#pragma once

namespace rt {

struct PrimResult {
  bool hit;
  bool err;  // the ray has NaN/inf in o or d, NaN tmin/tmax, or d = 0
  float t;   // on a miss t = u = v = +0; never NaN
  float u;   // weight of p1 (Embree/Nori convention: (1-u-v) p0 + u p1 + v p2)
  float v;   // weight of p2
};

// Final output stage of both kernels: on a miss t = u = v = +0, so no NaN or
// stale value ever leaves a kernel.
inline void set_prim_result(bool hit, bool err, float t, float u, float v, PrimResult* out) {
  out->hit = hit;
  out->err = err;
  out->t = hit ? t : 0.0f;
  out->u = hit ? u : 0.0f;
  out->v = hit ? v : 0.0f;
}

// Exactly coincident vertices (any pair, compared with IEEE ==). Such a
// triangle is never hit by either kernel. 9 comparators, no arithmetic.
inline bool coincident_vertices(const float p0[3], const float p1[3], const float p2[3]) {
  bool e01 = true, e12 = true, e02 = true;
  for (int i = 0; i < 3; ++i) {
    e01 = e01 && p0[i] == p1[i];
    e12 = e12 && p1[i] == p2[i];
    e02 = e02 && p0[i] == p2[i];
  }
  return e01 || e12 || e02;
}

}  // namespace rt
