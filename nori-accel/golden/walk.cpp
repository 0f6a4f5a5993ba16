// The golden walk (walk.h). Operation order and every decision follow the
// Scala golden model the RTL is checked against: RayKernel + BoxKernel
// (conservative) + WatertightKernel, ControlGolden.step, TraversalGolden.trace.
#include "walk.h"

#include <algorithm>
#include <utility>

#include "../../hls/prim_wt.h"
#include "directed.h"

namespace rtg {
namespace {

constexpr uint32_t kEmptySlot = 0x40000000u;  // wide layouts' empty-slot word0
constexpr uint32_t kLeafBit = 0x80000000u;

bool nonfinite_word(float x) { return rt::is_nonfinite(x); }

// RayKernel in FP32, conservative: RTZ and RUP reciprocals of |d| for the
// box, the watertight shear from the RNE reciprocal (R4).
struct Prepared {
  float o[3], d[3], tmin, tmax;
  float rcp_lo[3], rcp_hi[3];
  bool dir_neg[3];
  bool err;
  rt::RayShear shear;
};

Prepared prepare(const RayIn& r) {
  Prepared p;
  for (int i = 0; i < 3; ++i) {
    p.o[i] = r.o[i];
    p.d[i] = r.d[i];
    const float m = std::fabs(r.d[i]);
    p.rcp_lo[i] = recip_dir(m, Dir::Down);  // RTZ = RDN for a positive quotient
    p.rcp_hi[i] = recip_dir(m, Dir::Up);
    p.dir_neg[i] = rt::sign_bit(r.d[i]);
  }
  p.tmin = r.tmin;  // FP32 -> FP32 narrowing is the identity in every mode
  p.tmax = r.tmax;
  p.err = rt::ray_error(p.o, p.d, p.tmin, p.tmax);
  p.shear = rt::make_shear(rt::make_ray(p.o, p.d, p.tmin, p.tmax));
  return p;
}

bool lt_zero(float x) { return rt::sign_bit(x) && !rt::is_zero(x) && !rt::is_nan(x); }
bool gt_zero(float x) { return !rt::sign_bit(x) && !rt::is_zero(x) && !rt::is_nan(x); }

// BoxKernel, conservative FP32: (hit, near).
bool box_test(const Prepared& r, float tmax, const NodeRec& n, float* near_out) {
  float near = -rt::kInf, far = rt::kInf;
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    const float bmin = n.bmin[i], bmax = n.bmax[i], o = r.o[i], d = r.d[i];
    const float a = sub_dir(bmin, o, Dir::Down);  // B1
    const float b = sub_dir(bmax, o, Dir::Up);    // B2
    const float r_min = lt_zero(a) ? r.rcp_hi[i] : r.rcp_lo[i];
    const float r_max = gt_zero(b) ? r.rcp_hi[i] : r.rcp_lo[i];
    const float p_min = mul_dir(a, r_min, Dir::Down);  // B3, magnitude form
    const float p_max = mul_dir(b, r_max, Dir::Up);    // B4
    const bool flat = rt::is_zero(d);                  // B6
    const bool neg = rt::sign_bit(d);                  // B5
    const float lo = flat ? -rt::kInf : (neg ? -p_max : p_min);
    const float hi = flat ? rt::kInf : (neg ? -p_min : p_max);
    const bool in = !flat || (o >= bmin && o <= bmax);
    const bool valid = bmin <= bmax;  // B7
    ok = ok && in && valid;
    near = rt::max_num(near, lo);  // B8
    far = rt::min_num(far, hi);
  }
  *near_out = near;
  return !r.err && ok && near <= far && r.tmin <= far && near <= tmax;  // B9
}

struct Ref {
  bool leaf;
  uint32_t index, count;
};

}  // namespace

HitOut trace(const Image& img, const RayIn& ray, const WalkConfig& cfg, WalkStats* stats) {
  const Prepared p = prepare(ray);
  const int slots = img.slots();
  const bool nori = img.layout == 0;
  Ref stack[256];
  const int depth = std::min(cfg.stack_depth, 256);
  int sp = 0;
  uint32_t errors = p.err ? (1u << kInvalidRay) : 0u;
  float tmax = p.tmax;
  bool have = false, occluded = false;
  float bt = 0, bu = 0, bv = 0;
  uint32_t bprim = 0;
  uint32_t node = 0;
  bool from_leaf = false;
  uint64_t box_tests = 0, tri_tests = 0;

  // Runs a leaf as LeafIntersect does: every triangle against the tmax the
  // leaf had on entry; smallest t (order key), ties to the lower prim; a
  // shadow ray stops at its first occluder.
  auto run_leaf = [&](uint32_t first, uint32_t count) {
    const float leaf_tmax = tmax;
    if (static_cast<uint64_t>(first) + count > img.tris.size()) { errors |= 1u << kIndexOverflow; return; }
    for (uint32_t i = 0; i < count && !(ray.shadow && occluded); ++i) {
      const TriRec& t = img.tris[first + i];
      ++tri_tests;
      for (int k = 0; k < 9; ++k)
        if (nonfinite_word(t.v[k / 3][k % 3])) errors |= 1u << kBadSceneData;
      rt::PrimResult r;
      rt::prim_intersect_wt(p.o, p.d, p.tmin, leaf_tmax, p.shear, t.v[0], t.v[1], t.v[2], &r);
      if (!r.hit) continue;
      const int64_t k = rt::order_key(r.t), bk = rt::order_key(bt);
      if (!have || k < bk || (k == bk && t.prim < bprim)) {
        have = true; bt = r.t; bu = r.u; bv = r.v; bprim = t.prim;
      }
      if (ray.shadow) occluded = true;
    }
    if (have) tmax = bt;
  };

  for (;;) {
    bool chosen = false;
    Ref next{};
    Ref pushes[8];
    int npush = 0;
    if (!from_leaf) {
      ++box_tests;
      if (node >= img.node_count) { errors |= 1u << kIndexOverflow; break; }
      const NodeRec* rec = &img.records[static_cast<size_t>(node) * slots];
      // Decode errors of the used slots (BvhNode.decode / TraversalGolden.nodeView).
      struct Hit { float near; int slot; };
      Hit hits[8];
      int nh = 0;
      for (int s = 0; s < slots; ++s) {
        const NodeRec& n = rec[s];
        const bool present = nori || n.word0 != kEmptySlot;
        if (!present) continue;
        const bool leaf = (n.word0 & kLeafBit) != 0;
        const uint32_t low31 = n.word0 & 0x7fffffffu;
        const bool bad_kind = nori ? (!leaf && low31 > 2) : (!leaf && n.word0 != 0);
        if (bad_kind) errors |= 1u << kIndexOverflow;
        if (leaf && low31 > cfg.max_leaf_size) errors |= 1u << kLeafTooBig;
        for (int k = 0; k < 3; ++k)
          if (nonfinite_word(n.bmin[k]) || nonfinite_word(n.bmax[k])) errors |= 1u << kBadSceneData;
        float near;
        if (box_test(p, tmax, n, &near)) hits[nh++] = Hit{near, s};
      }
      if (nori) {
        const NodeRec& n = rec[0];
        if (nh > 0) {
          chosen = true;
          if (n.word0 & kLeafBit) {
            next = Ref{true, n.word1, n.word0 & 0x7fffffffu};
          } else {
            const Ref left{false, node + 1, 0}, right{false, n.word1, 0};
            // An axis word of 3 is flagged IndexOverflow above (the ray ends);
            // read it as x meanwhile so the index stays in range.
            const uint32_t axis = n.word0 & 3u;
            const bool neg = p.dir_neg[axis == 3u ? 0u : axis];
            next = neg ? right : left;
            pushes[npush++] = neg ? left : right;
          }
        }
      } else if (nh > 0) {
        // Nearest first by order key, ties to the lower slot.
        // Insertion sort: at most 8 entries.
        for (int j = 1; j < nh; ++j)
          for (int k = j; k > 0; --k) {
            const int64_t ka = rt::order_key(hits[k].near), kb = rt::order_key(hits[k - 1].near);
            if (ka < kb || (ka == kb && hits[k].slot < hits[k - 1].slot)) std::swap(hits[k], hits[k - 1]);
            else break;
          }
        auto ref_of = [&](int s) {
          const NodeRec& n = rec[s];
          return (n.word0 & kLeafBit) ? Ref{true, n.word1, n.word0 & 0x7fffffffu} : Ref{false, n.word1, 0};
        };
        chosen = true;
        next = ref_of(hits[0].slot);
        for (int j = nh - 1; j >= 1; --j) pushes[npush++] = ref_of(hits[j].slot);  // farthest at the bottom
      }
    }
    if (chosen && sp + npush > depth) errors |= 1u << kStackOverflow;
    const bool finished = errors != 0 || (from_leaf && occluded) || (!chosen && sp == 0);
    if (finished) break;
    if (!chosen) next = stack[--sp];
    else for (int j = 0; j < npush; ++j) stack[sp++] = pushes[j];
    if (next.leaf) {
      run_leaf(next.index, next.count);
      from_leaf = true;
    } else {
      node = next.index;
      from_leaf = false;
    }
  }
  if (stats) { stats->box_tests += box_tests; stats->tri_tests += tri_tests; }
  const bool hit = errors == 0 && have;
  HitOut h;
  h.hit = hit;
  h.t = hit ? bt : 0.0f;
  h.u = hit ? bu : 0.0f;
  h.v = hit ? bv : 0.0f;
  h.prim = hit ? static_cast<int64_t>(bprim) : -1;
  h.errors = errors;
  return h;
}

}  // namespace rtg
