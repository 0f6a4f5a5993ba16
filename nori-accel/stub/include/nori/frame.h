// Test stand-in (see common.h): Nori's orthonormal frame (s, t, n) built from
// a unit normal. The tangents come from a branchless basis (Duff et al. 2017)
// written out by components, not with cross(), so that this header does not
// need <Eigen/Geometry> (common.h says why that matters).
#pragma once
#include <cmath>
#include <nori/common.h>

NORI_NAMESPACE_BEGIN
struct Frame {
  Vector3f s, t;
  Normal3f n;
  Frame() = default;
  Frame(const Vector3f& normal) : n(normal) {
    const float sign = std::copysign(1.0f, n.z());
    const float a = -1.0f / (sign + n.z());
    const float b = n.x() * n.y() * a;
    s = Vector3f(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    t = Vector3f(b, sign + n.y() * n.y() * a, -n.y());
  }
};
NORI_NAMESPACE_END
