// Test stand-in (see common.h): Nori's Ray3f (o, d, dRcp, mint, maxt).
#pragma once
#include <nori/common.h>

NORI_NAMESPACE_BEGIN
/// Nori's default ray epsilon for mint (Epsilon = 1e-4f in Nori's common.h).
constexpr float Epsilon = 1e-4f;

struct Ray3f {
  Point3f o;
  Vector3f d, dRcp;
  float mint = Epsilon, maxt = std::numeric_limits<float>::infinity();
  Ray3f() = default;
  Ray3f(const Point3f& o_, const Vector3f& d_) : o(o_), d(d_) { update(); }
  Ray3f(const Point3f& o_, const Vector3f& d_, float mint_, float maxt_) : o(o_), d(d_), mint(mint_), maxt(maxt_) { update(); }
  void update() { dRcp = Vector3f(1.0f / d.x(), 1.0f / d.y(), 1.0f / d.z()); }
};
NORI_NAMESPACE_END
