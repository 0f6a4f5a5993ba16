// Test stand-in (see common.h): Nori's vector, point and normal types, each
// an Eigen column vector with Nori's constructors (a constant, N scalars, any
// Eigen expression), so Eigen's whole interface is what the drop-in sees.
#pragma once
#include <nori/common.h>

NORI_NAMESPACE_BEGIN

namespace stub {
/// One Eigen column vector type with Nori's constructors; Tag only keeps
/// vectors, points and normals distinct types, as they are in Nori.
template <typename Scalar, int N, typename Tag>
struct Column : public Eigen::Matrix<Scalar, N, 1> {
  using Base = Eigen::Matrix<Scalar, N, 1>;
  Column(Scalar value = Scalar(0)) { Base::setConstant(value); }
  Column(Scalar x, Scalar y) : Base(x, y) {}
  Column(Scalar x, Scalar y, Scalar z) : Base(x, y, z) {}
  template <typename Derived>
  Column(const Eigen::MatrixBase<Derived>& e) : Base(e) {}
  template <typename Derived>
  Column& operator=(const Eigen::MatrixBase<Derived>& e) {
    Base::operator=(e);
    return *this;
  }
};
struct VectorTag {};
struct PointTag {};
}  // namespace stub

template <typename Scalar, int N>
struct TVector : public stub::Column<Scalar, N, stub::VectorTag> {
  using stub::Column<Scalar, N, stub::VectorTag>::Column;
};
template <typename Scalar, int N>
struct TPoint : public stub::Column<Scalar, N, stub::PointTag> {
  using stub::Column<Scalar, N, stub::PointTag>::Column;
};
struct Normal3f : public stub::Column<float, 3, Normal3f> {
  using stub::Column<float, 3, Normal3f>::Column;
};

NORI_NAMESPACE_END
