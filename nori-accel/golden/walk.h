// The golden walk: what the FP32 accelerator answers for one ray, bit for
// bit, in its default configuration (watertight triangles, conservative
// boxes; docs/kernels.md). It visits nodes in TraversalControl's order
// (src/main/scala/rtaccel/golden/ControlGolden.scala) and reduces leaves as
// LeafIntersect does (TraversalGolden.scala); the box kernel is BoxKernel's
// conservative mode in FP32, the triangle kernel is hls/prim_wt.cpp, which
// `make -C hls test` bit-compares with the Chisel datapath.
//
// Role: the bit-exact C++ twin of the Scala golden model
// (rtaccel.golden.TraversalGolden, what the RTL is checked against), for
// renderers (the Nori drop-in, make render) and for make regress SIM=cpp,
// which checks every hardware hit against it with no JVM (golden-trace
// --rtl-hits). The twin is proved by NoriAccelGoldenSpec
// (src/test/scala/rtaccel/golden/, in make test): every ray of the regression
// scenes and the hard cases against TraversalGolden, bit for bit.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtg {

// ErrorFlags bit numbers (src/main/scala/rtaccel/ErrorFlags.scala).
enum ErrorBit : uint32_t { kStackOverflow = 0, kIndexOverflow = 1, kLeafTooBig = 2, kInvalidRay = 3, kBadSceneData = 4 };

// One 32-byte node record (a nori node or one wide slot).
struct NodeRec {
  uint32_t word0, word1;
  float bmin[3], bmax[3];
};

// One triangle record (44 bytes of fields in a 64-byte slot).
struct TriRec {
  float v[3][3];
  uint32_t prim, flags;
};

// A parsed memory image (docs/memory-format.md, version 3).
struct Image {
  uint32_t layout = 0;      // 0 = nori, else K slots per node
  uint32_t node_count = 0;  // nori nodes, or wide nodes
  uint32_t bvh_depth = 0;
  uint32_t max_leaf_size = 0;
  std::vector<NodeRec> records;  // node_count x max(1, layout) records
  std::vector<TriRec> tris;
  int slots() const { return layout == 0 ? 1 : static_cast<int>(layout); }
};

// Parses image.bin bytes; on failure returns false and says why in `err`.
bool parse_image(const uint8_t* bytes, size_t len, Image& out, std::string& err);

struct RayIn {
  float o[3], d[3], tmin, tmax;
  bool shadow;
};

// The hardware's answer: hit, t/u/v bits and prim when hit (else +0 and -1),
// the ErrorFlags bits. For a shadow ray only hit and errors are meaningful.
struct HitOut {
  bool hit;
  float t, u, v;
  int64_t prim;
  uint32_t errors;
};

// Work counters of one ray (box tests = node visits, triangle tests).
struct WalkStats {
  uint64_t box_tests = 0, tri_tests = 0;
};

// The hardware's stack depth (AccelConfig.stackDepth, 64 by default) and
// largest leaf (AccelConfig.maxLeafSize, 16).
struct WalkConfig {
  int stack_depth = 64;
  uint32_t max_leaf_size = 16;
};

HitOut trace(const Image& img, const RayIn& ray, const WalkConfig& cfg, WalkStats* stats = nullptr);

// The four-slot SIMD box test (AVX-512, when compiled in) against four
// scalar box tests on `n` seeded random rays and nodes, special values mixed
// in (zeros of both signs, subnormals, infinities, NaN, FLT_MAX): returns how
// many slots differ (hit, or the bits of near), printing the first few;
// -1 when the build has no SIMD box test. tests/directed_check.cpp runs it.
long box4_selfcheck(uint64_t seed, long n);

}  // namespace rtg
