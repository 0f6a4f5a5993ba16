// Test stand-in (see common.h): Nori's BoundingBox3f members the drop-in uses.
#pragma once
#include <limits>
#include <nori/common.h>

NORI_NAMESPACE_BEGIN
struct BoundingBox3f {
  Point3f min, max;
  BoundingBox3f() { reset(); }
  BoundingBox3f(const Point3f& a, const Point3f& b) : min(a), max(b) {}
  void reset() {
    const float inf = std::numeric_limits<float>::infinity();
    min = Point3f(inf, inf, inf);
    max = Point3f(-inf, -inf, -inf);
  }
  bool isValid() const { return min.x() <= max.x() && min.y() <= max.y() && min.z() <= max.z(); }
  void expandBy(const Point3f& p) {
    for (int i = 0; i < 3; ++i) { min[i] = std::fmin(min[i], p[i]); max[i] = std::fmax(max[i], p[i]); }
  }
  void expandBy(const BoundingBox3f& b) { expandBy(b.min); expandBy(b.max); }
};
NORI_NAMESPACE_END
