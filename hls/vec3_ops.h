// The two composite operations both triangle kernels use, with their rounding
// order fixed (each step one IEEE operation, RNE, no FMA).
#pragma once

namespace rt {

// Cross product, Eigen's order: c[i] = a[j]*b[k] - a[k]*b[j], (i,j,k) cyclic.
inline void cross3(const float a[3], const float b[3], float c[3]) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

// Dot product in the order Eigen's fixed-size redux uses for 3 elements
// (it splits [0,3) into [0,1) and [1,3)): a0*b0 + (a1*b1 + a2*b2).
// Nori's Vector3f::dot compiles to exactly this, so the MT kernel matches it.
inline float dot3(const float a[3], const float b[3]) {
  const float p0 = a[0] * b[0];
  const float p1 = a[1] * b[1];
  const float p2 = a[2] * b[2];
  return p0 + (p1 + p2);
}

}  // namespace rt
