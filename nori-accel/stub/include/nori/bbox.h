// Test stand-in (see common.h): Nori's axis-aligned box over a point type.
#pragma once
#include <nori/common.h>

NORI_NAMESPACE_BEGIN
template <typename Point>
struct TBoundingBox {
  Point min, max;
  TBoundingBox() { reset(); }
  TBoundingBox(const Point& a, const Point& b) : min(a), max(b) {}
  /// Empty: min = +inf, max = -inf, so the first expandBy sets both.
  void reset() {
    min.setConstant(std::numeric_limits<typename Point::Scalar>::infinity());
    max.setConstant(-std::numeric_limits<typename Point::Scalar>::infinity());
  }
  bool isValid() const { return (max.array() >= min.array()).all(); }
  void expandBy(const Point& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void expandBy(const TBoundingBox& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
};
NORI_NAMESPACE_END
