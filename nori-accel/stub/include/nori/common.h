// Test stand-in for Nori's types, written for rtaccel from Nori's documented
// interface (no Nori code): the names, members and signatures the drop-in
// uses, with the same meaning, so nori-accel/src/accel.cpp compiles
// unchanged against this header set and against Nori's own. Nori builds
// these on Eigen; here they are small structs with the same member
// functions. Only for nori-accel's tests: a Nori build uses Nori's headers.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>

#define NORI_NAMESPACE_BEGIN namespace nori {
#define NORI_NAMESPACE_END }

NORI_NAMESPACE_BEGIN

/// A 3-vector with Eigen's member names (x(), cross, dot, normalized).
struct Vector3f {
  float v[3] = {0, 0, 0};
  Vector3f() = default;
  Vector3f(float x, float y, float z) : v{x, y, z} {}
  float x() const { return v[0]; }
  float y() const { return v[1]; }
  float z() const { return v[2]; }
  float operator[](int i) const { return v[i]; }
  float& operator[](int i) { return v[i]; }
  float operator()(int i) const { return v[i]; }
  Vector3f operator+(const Vector3f& o) const { return {v[0] + o.v[0], v[1] + o.v[1], v[2] + o.v[2]}; }
  Vector3f operator-(const Vector3f& o) const { return {v[0] - o.v[0], v[1] - o.v[1], v[2] - o.v[2]}; }
  Vector3f operator*(float s) const { return {v[0] * s, v[1] * s, v[2] * s}; }
  Vector3f operator-() const { return {-v[0], -v[1], -v[2]}; }
  friend Vector3f operator*(float s, const Vector3f& a) { return a * s; }
  // Eigen's orders (docs/kernels.md): cross a[j]b[k] - a[k]b[j]; dot a0b0 + (a1b1 + a2b2).
  Vector3f cross(const Vector3f& o) const {
    return {v[1] * o.v[2] - v[2] * o.v[1], v[2] * o.v[0] - v[0] * o.v[2], v[0] * o.v[1] - v[1] * o.v[0]};
  }
  float dot(const Vector3f& o) const { return v[0] * o.v[0] + (v[1] * o.v[1] + v[2] * o.v[2]); }
  float squaredNorm() const { return dot(*this); }
  float norm() const { return std::sqrt(squaredNorm()); }
  Vector3f normalized() const { const float n = norm(); return n > 0 ? *this * (1.0f / n) : *this; }
};
using Point3f = Vector3f;
using Normal3f = Vector3f;

struct Point2f {
  float v[2] = {0, 0};
  Point2f() = default;
  Point2f(float x, float y) : v{x, y} {}
  float x() const { return v[0]; }
  float y() const { return v[1]; }
  float operator[](int i) const { return v[i]; }
  float sum() const { return v[0] + v[1]; }
  Point2f operator+(const Point2f& o) const { return {v[0] + o.v[0], v[1] + o.v[1]}; }
  friend Point2f operator*(float s, const Point2f& a) { return {s * a.v[0], s * a.v[1]}; }
};

/// Column-major dynamic matrix with Eigen's accessors (rows x cols), float or uint32_t.
template <typename T>
struct Matrix {
  int64_t r = 0, c = 0;
  std::basic_string<T> data;  // contiguous storage
  Matrix() = default;
  Matrix(int64_t rows, int64_t cols) : r(rows), c(cols), data(static_cast<size_t>(rows * cols), T()) {}
  int64_t rows() const { return r; }
  int64_t cols() const { return c; }
  int64_t size() const { return r * c; }
  T operator()(int64_t i, int64_t j) const { return data[static_cast<size_t>(j * r + i)]; }
  T& operator()(int64_t i, int64_t j) { return data[static_cast<size_t>(j * r + i)]; }
  Vector3f col(int64_t j) const { return {static_cast<float>((*this)(0, j)), static_cast<float>((*this)(1, j)), static_cast<float>(r > 2 ? (*this)(2, j) : 0)}; }
};
using MatrixXf = Matrix<float>;
using MatrixXu = Matrix<uint32_t>;

NORI_NAMESPACE_END
