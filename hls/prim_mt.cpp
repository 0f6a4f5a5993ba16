// HLS kernel: Moller-Trumbore in Nori's operation order (src/mesh.cpp,
// Mesh::rayIntersect), FP32 RNE. Nori returns early on a miss; hardware
// computes every value and decides at the end, which gives the same hit and
// the same t, u, v on every hit.
#include "prim_mt.h"
#include "fp32.h"
#include "ray_setup.h"
#include "vec3_ops.h"

namespace rt {

void prim_intersect_mt(const float o[3], const float d[3], float tmin, float tmax,
                       const float p0[3], const float p1[3], const float p2[3],
                       PrimResult* out) {
#pragma HLS PIPELINE II=1
#pragma HLS INTERFACE ap_ctrl_none port=return
#pragma HLS ARRAY_PARTITION variable=o complete
#pragma HLS ARRAY_PARTITION variable=d complete
#pragma HLS ARRAY_PARTITION variable=p0 complete
#pragma HLS ARRAY_PARTITION variable=p1 complete
#pragma HLS ARRAY_PARTITION variable=p2 complete
  float edge1[3], edge2[3], tvec[3], pvec[3], qvec[3];
#pragma HLS ARRAY_PARTITION variable=edge1 complete
#pragma HLS ARRAY_PARTITION variable=edge2 complete
#pragma HLS ARRAY_PARTITION variable=tvec complete
#pragma HLS ARRAY_PARTITION variable=pvec complete
#pragma HLS ARRAY_PARTITION variable=qvec complete
  for (int i = 0; i < 3; ++i) {
#pragma HLS UNROLL
    edge1[i] = p1[i] - p0[i];  // M1
    edge2[i] = p2[i] - p0[i];  // M2
    tvec[i] = o[i] - p0[i];    // M3
  }
  cross3(d, edge2, pvec);                  // M4
  const float det = dot3(edge1, pvec);     // M5
  const bool parallel = det > -kMtDetEpsilon && det < kMtDetEpsilon;  // M6
  const float inv_det = 1.0f / det;        // M7 (the only division)
  const float u = dot3(tvec, pvec) * inv_det;  // M8
  cross3(tvec, edge1, qvec);               // M9
  const float v = dot3(d, qvec) * inv_det;     // M10
  const float uv = u + v;                      // M11
  const float t = dot3(edge2, qvec) * inv_det; // M12
  // M13: Nori's tests, written as Nori writes them (a NaN u or v passes
  // Nori's `u < 0 || u > 1`); the extra !is_nan(u), !is_nan(v) only differ
  // from Nori where Nori would return a hit with a NaN u or v.
  const bool u_ok = !(u < 0.0f || u > 1.0f) && !is_nan(u);
  const bool v_ok = !(v < 0.0f || uv > 1.0f) && !is_nan(v);
  const bool t_ok = t >= tmin && t <= tmax;
  const bool err = ray_error(o, d, tmin, tmax);
  const bool hit = !err && !coincident_vertices(p0, p1, p2) && !parallel && u_ok && v_ok && t_ok;
  set_prim_result(hit, err, t, u, v, out);
}

}  // namespace rt
