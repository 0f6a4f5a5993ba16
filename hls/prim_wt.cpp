// HLS kernel: watertight ray/triangle test. Per-ray shear constants come in
// precomputed (make_shear); everything per triangle is below, FP32 RNE.
#include "prim_wt.h"
#include "fp32.h"

namespace rt {

namespace {

struct Sheared { float x, y, z; };

// W1..W3 for one vertex: translate to the ray origin, shear, scale z.
inline Sheared shear_vertex(const float p[3], const float o[3], const RayShear& s) {
  float rel[3];
#pragma HLS ARRAY_PARTITION variable=rel complete
  for (int i = 0; i < 3; ++i) {
#pragma HLS UNROLL
    rel[i] = p[i] - o[i];  // W1
  }
  Sheared r;
  r.x = rel[s.kx] - s.sx * rel[s.kz];  // W2: one product, one difference
  r.y = rel[s.ky] - s.sy * rel[s.kz];
  r.z = s.sz * rel[s.kz];              // W3 (only needed for T)
  return r;
}

// W4: U, V, W in the paper's naming, each the edge function of the two other
// vertices (U is opposite A, V opposite B, W opposite C).
inline EdgeValues edges_of(const Sheared& a, const Sheared& b, const Sheared& c) {
  EdgeValues e;
  e.u = edge_function(c.x, c.y, b.x, b.y);
  e.v = edge_function(a.x, a.y, c.x, c.y);
  e.w = edge_function(b.x, b.y, a.x, a.y);
  return e;
}

// W9: scale by 1/det, but an exact zero stays +0: with |det| <= 2^-128 the
// reciprocal overflows to inf and 0 * inf would be NaN on a point that lies
// exactly on an edge (the tie case the test must keep).
inline float scale(float x, float rcp_det) { return is_zero(x) ? 0.0f : x * rcp_det; }

}  // namespace

EdgeValues wt_edge_values(const float o[3], const RayShear& s,
                          const float p0[3], const float p1[3], const float p2[3]) {
  return edges_of(shear_vertex(p0, o, s), shear_vertex(p1, o, s), shear_vertex(p2, o, s));
}

void prim_intersect_wt(const float o[3], const float d[3], float tmin, float tmax,
                       const RayShear& shear,
                       const float p0[3], const float p1[3], const float p2[3],
                       PrimResult* out) {
#pragma HLS PIPELINE II=1
#pragma HLS INTERFACE ap_ctrl_none port=return
#pragma HLS ARRAY_PARTITION variable=o complete
#pragma HLS ARRAY_PARTITION variable=d complete
#pragma HLS ARRAY_PARTITION variable=p0 complete
#pragma HLS ARRAY_PARTITION variable=p1 complete
#pragma HLS ARRAY_PARTITION variable=p2 complete
  const Sheared a = shear_vertex(p0, o, shear);
  const Sheared b = shear_vertex(p1, o, shear);
  const Sheared c = shear_vertex(p2, o, shear);
  const EdgeValues e = edges_of(a, b, c);
  // W5: tie rule. Zero (either sign) counts as inside; a miss needs a strictly
  // negative and a strictly positive edge value.
  const bool any_neg = e.u < 0.0f || e.v < 0.0f || e.w < 0.0f;
  const bool any_pos = e.u > 0.0f || e.v > 0.0f || e.w > 0.0f;
  const bool outside = any_neg && any_pos;
  const float det = (e.u + e.v) + e.w;                        // W6
  const float t_num = (e.u * a.z + e.v * b.z) + e.w * c.z;    // W7
  const float rcp_det = 1.0f / det;                           // W8 (the only division)
  const float t = scale(t_num, rcp_det);                      // W9
  const float u = scale(e.v, rcp_det);  // weight of p1 (B)
  const float v = scale(e.w, rcp_det);  // weight of p2 (C)
  // W10: det must be finite and non-zero. A finite det implies U, V, W finite
  // (they share a sign), so u, v are never NaN; t is NaN only if T overflowed
  // to inf - inf, and a NaN t fails the range test.
  const bool det_ok = !is_zero(det) && !is_nonfinite(det);
  const bool t_ok = t >= tmin && t <= tmax;
  const bool err = ray_error(o, d, tmin, tmax);
  const bool hit = !err && !coincident_vertices(p0, p1, p2) && !outside && det_ok && t_ok;
  set_prim_result(hit, err, t, u, v, out);
}

}  // namespace rt
