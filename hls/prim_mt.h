// PrimIntersect, Nori-compatible Moller-Trumbore variant (FP32).
// Operation sequence: docs/kernels.md, "PrimIntersect (Moller-Trumbore)".
#pragma once
#include "prim_result.h"

namespace rt {

// |det| below this is "ray parallel to the plane": Nori's 1e-8f, i.e. the
// float nearest 1e-8 (bits 0x322bcc77). Kept for bit-compatibility with Nori,
// not derived from an error bound.
constexpr float kMtDetEpsilon = 1e-8f;

void prim_intersect_mt(const float o[3], const float d[3], float tmin, float tmax,
                       const float p0[3], const float p1[3], const float p2[3],
                       PrimResult* out);

}  // namespace rt
