// Test stand-in for Nori's include/nori/common.h, written for rtaccel from
// Nori's documented interface (no Nori code). Only for nori-accel's tests: a
// Nori build uses Nori's own headers. What matters is the shape, so that
// nori-accel/src/accel.cpp meets here what it meets in Nori:
//   - the types are Eigen's (Debian's libeigen3-dev, as Nori builds on Eigen):
//     vectors and points are Eigen::Matrix<float, N, 1>, meshes' arrays are
//     dynamic Eigen matrices;
//   - this header includes <Eigen/Core> only, as Nori's does. Eigen declares
//     cross() in Core but defines it in <Eigen/Geometry>, so a drop-in that
//     calls cross() without including Geometry fails to link, here as in Nori.
//     For that check to hold, nothing else linked into the tests may include
//     <Eigen/Geometry> (it would supply the definition).
//   - Epsilon is a macro, as in Nori: a drop-in identifier named Epsilon
//     breaks here as it would there.
#pragma once
#include <cstdint>
#include <limits>
#include <string>

#include <Eigen/Core>

#define NORI_NAMESPACE_BEGIN namespace nori {
#define NORI_NAMESPACE_END }

/// Nori's ray epsilon: the default mint of a ray.
#define Epsilon 1e-4f

NORI_NAMESPACE_BEGIN

template <typename Scalar, int Dimension> struct TVector;
template <typename Scalar, int Dimension> struct TPoint;
template <typename Point, typename Vector> struct TRay;
template <typename Point> struct TBoundingBox;
struct Normal3f;
struct Frame;
struct Intersection;
class Mesh;

using Vector2f = TVector<float, 2>;
using Vector3f = TVector<float, 3>;
using Point2f = TPoint<float, 2>;
using Point3f = TPoint<float, 3>;
using Ray3f = TRay<Point3f, Vector3f>;
using BoundingBox3f = TBoundingBox<Point3f>;

/// Column-major, 3 x N (positions, normals), 2 x N (texture coordinates), 3 x M (indices).
using MatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;
using MatrixXu = Eigen::Matrix<uint32_t, Eigen::Dynamic, Eigen::Dynamic>;

NORI_NAMESPACE_END

#include <nori/vector.h>
