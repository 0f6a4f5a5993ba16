// PrimIntersect, watertight variant (Woop, Benthin, Wald, JCGT 2013) with a
// sign-symmetric tie rule instead of the paper's double-precision fallback.
// Operation sequence: docs/kernels.md, "PrimIntersect (watertight)".
#pragma once
#include "prim_result.h"
#include "ray_setup.h"

namespace rt {

// Edge function of two sheared vertices: E(P, Q) = Px*Qy - Py*Qx, two RNE
// products and one RNE subtraction. RNE is sign-symmetric and products
// commute exactly, so E(Q, P) == -E(P, Q) bit for bit (up to the sign of a
// zero): an edge shared by two triangles gets exactly opposite values.
inline float edge_function(float px, float py, float qx, float qy) {
  const float a = px * qy;
  const float b = py * qx;
  return a - b;
}

// The three edge functions of the kernel, exposed so the tests can check the
// exact antisymmetry on every shared edge of a closed mesh.
struct EdgeValues { float u, v, w; };
EdgeValues wt_edge_values(const float o[3], const RayShear& s,
                          const float p0[3], const float p1[3], const float p2[3]);

void prim_intersect_wt(const float o[3], const float d[3], float tmin, float tmax,
                       const RayShear& shear,
                       const float p0[3], const float p1[3], const float p2[3],
                       PrimResult* out);

}  // namespace rt
