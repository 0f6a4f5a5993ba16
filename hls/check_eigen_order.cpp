// One-off evidence for the dot-product order of the MT kernel (not part of
// `make test`; needs libeigen3-dev): `make -C hls eigen-order`.
// Nori's Vector3f is an Eigen fixed-size vector. This program checks, on
// seeded random vectors, that Eigen's dot equals a0*b0 + (a1*b1 + a2*b2)
// (vec3_ops.h, dot3) and its cross equals cross3, bit for bit, and fails
// otherwise.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdio>

#include "fp32.h"
#include "rng.h"
#include "vec3_ops.h"

int main() {
  rt::Rng rng(0x5eed0004ull);
  long differ = 0, bad = 0;
  const long n = 1000000;
  for (long k = 0; k < n; ++k) {
    Eigen::Vector3f a, b;
    float fa[3], fb[3], fc[3];
    for (int i = 0; i < 3; ++i) {
      fa[i] = a[i] = static_cast<float>(rng.uniform(-1, 1) * rng.pow2(-10, 10));
      fb[i] = b[i] = static_cast<float>(rng.uniform(-1, 1) * rng.pow2(-10, 10));
    }
    const float left = (fa[0] * fb[0] + fa[1] * fb[1]) + fa[2] * fb[2];
    differ += rt::bits(left) != rt::bits(rt::dot3(fa, fb));
    const Eigen::Vector3f c = a.cross(b);
    rt::cross3(fa, fb, fc);
    bad += rt::bits(a.dot(b)) != rt::bits(rt::dot3(fa, fb));
    for (int i = 0; i < 3; ++i) bad += rt::bits(c[i]) != rt::bits(fc[i]);
  }
  std::printf("eigen-order: Eigen %d.%d.%d, %ld vectors, %ld where (a0b0+a1b1)+a2b2 differs from a0b0+(a1b1+a2b2); "
              "%ld mismatches against dot3/cross3\n",
              EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION, n, differ, bad);
  return bad == 0 ? 0 : 1;
}
