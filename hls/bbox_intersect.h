// BboxIntersect: slab test of one ray against one axis-aligned box (FP32).
// Operation sequence: docs/kernels.md, "BboxIntersect".
#pragma once

namespace rt {

struct BoxResult {
  bool hit;
  bool err;    // the ray has NaN/inf in o or d, NaN tmin/tmax, or d = 0
  float near;  // entry distance max_i(near_i); never NaN; -inf if no axis bounds it
};

void bbox_intersect(const float o[3], const float d[3], const float rcp[3],
                    float tmin, float tmax,
                    const float bmin[3], const float bmax[3], BoxResult* out);

}  // namespace rt
