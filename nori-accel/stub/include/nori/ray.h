// Test stand-in (see common.h): Nori's ray (o, d, dRcp, mint, maxt).
#pragma once
#include <nori/common.h>

NORI_NAMESPACE_BEGIN
template <typename Point, typename Vector>
struct TRay {
  using Scalar = typename Point::Scalar;
  Point o;
  Vector d, dRcp;
  Scalar mint = Epsilon, maxt = std::numeric_limits<Scalar>::infinity();
  TRay() = default;
  TRay(const Point& o_, const Vector& d_) : o(o_), d(d_) { update(); }
  TRay(const Point& o_, const Vector& d_, Scalar mint_, Scalar maxt_) : o(o_), d(d_), mint(mint_), maxt(maxt_) { update(); }
  void update() { dRcp = d.cwiseInverse(); }
};
NORI_NAMESPACE_END
