// Parses the version-3 memory image (docs/memory-format.md). The checks are
// the header's: the walk trusts indices it has bounds-checked here.
#include "walk.h"

#include <cstring>

namespace rtg {
namespace {
constexpr uint32_t kVersion = 3;
constexpr uint32_t kTriBytes = 64;  // a triangle record's stride: one 64-byte line
uint32_t u32(const uint8_t* p) {
  uint32_t x;
  std::memcpy(&x, p, 4);  // little-endian host (x86-64, ARM): the file's order
  return x;
}
float f32(const uint8_t* p) {
  float x;
  std::memcpy(&x, p, 4);
  return x;
}
}  // namespace

bool parse_image(const uint8_t* b, size_t len, Image& out, std::string& err) {
  if (len < 64 || std::memcmp(b, "RTACCEL\0", 8) != 0) { err = "not an rtaccel memory image (magic)"; return false; }
  if (u32(b + 8) != kVersion) {
    err = "image version " + std::to_string(u32(b + 8)) + ", this reader takes " + std::to_string(kVersion);
    return false;
  }
  out.node_count = u32(b + 12);
  const uint32_t tri_count = u32(b + 16), node_off = u32(b + 20), tri_off = u32(b + 24);
  const uint32_t node_bytes = u32(b + 28), tri_bytes = u32(b + 32);
  out.max_leaf_size = u32(b + 36);
  out.bvh_depth = u32(b + 40);
  out.layout = u32(b + 44);
  if (!(out.layout == 0 || out.layout == 2 || out.layout == 4 || out.layout == 8)) {
    err = "layout word " + std::to_string(out.layout) + " (0, 2, 4 or 8)";
    return false;
  }
  const size_t slots = static_cast<size_t>(out.slots());
  if (node_bytes != 32 * slots || tri_bytes != kTriBytes) { err = "record sizes do not match the layout"; return false; }
  if (node_off + static_cast<size_t>(node_bytes) * out.node_count > tri_off ||
      tri_off + static_cast<size_t>(kTriBytes) * tri_count != len) {
    err = "section offsets do not match the file length";
    return false;
  }
  out.records.resize(slots * out.node_count);
  for (size_t i = 0; i < out.records.size(); ++i) {
    const uint8_t* p = b + node_off + 32 * i;
    NodeRec& n = out.records[i];
    n.word0 = u32(p);
    n.word1 = u32(p + 4);
    for (int k = 0; k < 3; ++k) { n.bmin[k] = f32(p + 8 + 4 * k); n.bmax[k] = f32(p + 20 + 4 * k); }
  }
  out.tris.resize(tri_count);
  for (size_t i = 0; i < tri_count; ++i) {
    const uint8_t* p = b + tri_off + static_cast<size_t>(kTriBytes) * i;
    TriRec& t = out.tris[i];
    for (int k = 0; k < 9; ++k) t.v[k / 3][k % 3] = f32(p + 4 * k);
    t.prim = u32(p + 36);
    t.flags = u32(p + 40);
  }
  return true;
}

}  // namespace rtg
