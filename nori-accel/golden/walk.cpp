// The golden walk (walk.h). Operation order and every decision follow the
// Scala golden model the RTL is checked against: RayKernel + BoxKernel
// (conservative) + WatertightKernel, ControlGolden.step, TraversalGolden.trace.
#include "walk.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
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

#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
#define RTG_BOX4 1
// GCC 12's intrinsics headers start the unmasked AVX-512 forms from
// _mm512_undefined_ps(), which -Wmaybe-uninitialized reports (a false positive).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
// box_test for four slots at once (a wide node's slots s..s+3), the same
// operations in the same order per lane: AVX-512 embedded rounding is the
// IEEE directed rounding directed.h's scalar path uses (one instruction per
// operation there too), the comparisons are the same ordered IEEE ones, and
// max_num / min_num are done on order keys as rt::max_num / min_num do.
// Lanes 4i+s hold axis i of slot s (lanes 12..15 unused, masked off).
struct Box4Ray {
  __m512 o, rlo, rhi;
  __mmask16 flat, neg;
};

Box4Ray box4_ray(const Prepared& p) {
  Box4Ray v;
  auto lanes = [](const float x[3]) {
    return _mm512_setr_ps(x[0], x[0], x[0], x[0], x[1], x[1], x[1], x[1], x[2], x[2], x[2], x[2], x[0], x[0], x[0], x[0]);
  };
  v.o = lanes(p.o);
  v.rlo = lanes(p.rcp_lo);
  v.rhi = lanes(p.rcp_hi);
  const __m512 d = lanes(p.d);
  v.flat = _mm512_cmp_ps_mask(d, _mm512_setzero_ps(), _CMP_EQ_OQ);                          // B6: d = ±0
  v.neg = _mm512_test_epi32_mask(_mm512_castps_si512(d), _mm512_set1_epi32(INT32_MIN));      // B5: sign bit
  return v;
}

// Signed-integer order key of non-NaN floats (rt::order_key's order in 32 bits: -0 < +0).
inline __m128i key4(__m128 x) {
  const __m128i b = _mm_castps_si128(x);
  return _mm_xor_si128(b, _mm_and_si128(_mm_srai_epi32(b, 31), _mm_set1_epi32(0x7fffffff)));
}
// rt::max_num(a, b) / rt::min_num(a, b) for a never NaN (near, far start at ∓inf and stay numbers).
inline __m128 max_num4(__m128 a, __m128 b) {
  const __m128 pick_a = _mm_or_ps(_mm_cmpunord_ps(b, b), _mm_castsi128_ps(_mm_or_si128(_mm_cmpgt_epi32(key4(a), key4(b)),
                                                                                        _mm_cmpeq_epi32(key4(a), key4(b)))));
  return _mm_blendv_ps(b, a, pick_a);
}
inline __m128 min_num4(__m128 a, __m128 b) {
  const __m128 pick_a = _mm_or_ps(_mm_cmpunord_ps(b, b), _mm_castsi128_ps(_mm_or_si128(_mm_cmplt_epi32(key4(a), key4(b)),
                                                                                        _mm_cmpeq_epi32(key4(a), key4(b)))));
  return _mm_blendv_ps(b, a, pick_a);
}

// Returns the hit mask of the four slots (bit s) and their near values.
unsigned box_test4(const Prepared& r, const Box4Ray& v, float tmax, const NodeRec* rec, float near_out[4]) {
  const float* f = reinterpret_cast<const float*>(rec);  // 4 records of 8 words: word0, word1, bmin[3], bmax[3]
  const __m512 r01 = _mm512_loadu_ps(f), r23 = _mm512_loadu_ps(f + 16);
  const __m512i kMin = _mm512_setr_epi32(2, 10, 18, 26, 3, 11, 19, 27, 4, 12, 20, 28, 2, 2, 2, 2);
  const __m512i kMax = _mm512_setr_epi32(5, 13, 21, 29, 6, 14, 22, 30, 7, 15, 23, 31, 5, 5, 5, 5);
  const __m512 bmin = _mm512_permutex2var_ps(r01, kMin, r23), bmax = _mm512_permutex2var_ps(r01, kMax, r23);
  const __m512 zero = _mm512_setzero_ps();
  const __m512 a = _mm512_sub_round_ps(bmin, v.o, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);  // B1
  const __m512 b = _mm512_sub_round_ps(bmax, v.o, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);  // B2
  const __m512 r_min = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(a, zero, _CMP_LT_OQ), v.rlo, v.rhi);  // lt_zero(a)
  const __m512 r_max = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(b, zero, _CMP_GT_OQ), v.rlo, v.rhi);  // gt_zero(b)
  const __m512 p_min = _mm512_mul_round_ps(a, r_min, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);    // B3
  const __m512 p_max = _mm512_mul_round_ps(b, r_max, _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);    // B4
  const __m512 sign = _mm512_set1_ps(-0.0f);
  const __m512 inf = _mm512_set1_ps(rt::kInf), ninf = _mm512_set1_ps(-rt::kInf);
  __m512 lo = _mm512_mask_blend_ps(v.neg, p_min, _mm512_xor_ps(p_max, sign));
  __m512 hi = _mm512_mask_blend_ps(v.neg, p_max, _mm512_xor_ps(p_min, sign));
  lo = _mm512_mask_blend_ps(v.flat, lo, ninf);
  hi = _mm512_mask_blend_ps(v.flat, hi, inf);
  const __mmask16 inside = _mm512_cmp_ps_mask(v.o, bmin, _CMP_GE_OQ) & _mm512_cmp_ps_mask(v.o, bmax, _CMP_LE_OQ);
  const __mmask16 in = static_cast<__mmask16>(~v.flat | inside);
  const __mmask16 valid = _mm512_cmp_ps_mask(bmin, bmax, _CMP_LE_OQ);  // B7
  const unsigned okl = static_cast<unsigned>(in & valid);
  const unsigned ok = okl & (okl >> 4) & (okl >> 8) & 0xfu;
  __m128 near = _mm_set1_ps(-rt::kInf), far = _mm_set1_ps(rt::kInf);  // B8, axes in order x, y, z
  near = max_num4(near, _mm512_castps512_ps128(lo));
  far = min_num4(far, _mm512_castps512_ps128(hi));
  near = max_num4(near, _mm512_extractf32x4_ps(lo, 1));
  far = min_num4(far, _mm512_extractf32x4_ps(hi, 1));
  near = max_num4(near, _mm512_extractf32x4_ps(lo, 2));
  far = min_num4(far, _mm512_extractf32x4_ps(hi, 2));
  _mm_storeu_ps(near_out, near);
  const __m128 cmp = _mm_and_ps(_mm_and_ps(_mm_cmple_ps(near, far), _mm_cmple_ps(_mm_set1_ps(r.tmin), far)),
                                _mm_cmple_ps(near, _mm_set1_ps(tmax)));  // B9
  return r.err ? 0u : ok & static_cast<unsigned>(_mm_movemask_ps(cmp));
}
#pragma GCC diagnostic pop
#endif

struct Ref {
  bool leaf;
  uint32_t index, count;
};

}  // namespace

#ifdef RTG_BOX4
// As above: the SIMD box test inlined here draws the same false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
long box4_selfcheck(uint64_t seed, long n) {
#ifdef RTG_BOX4
  uint64_t st = seed | 1;
  auto u32 = [&] { st ^= st << 13; st ^= st >> 7; st ^= st << 17; return static_cast<uint32_t>(st >> 11); };
  const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 1.1754944e-38f, -1.1754944e-38f, 3.4028235e38f, -3.4028235e38f,
                           1.4e-45f, -1.4e-45f, rt::kInf, -rt::kInf, std::nanf(""), 1e-30f, -1e30f, 2.9e-39f};
  // A coordinate: mostly scene-like, sometimes special or any bit pattern.
  auto coord = [&] {
    const uint32_t k = u32() % 16;
    if (k < 3) return special[u32() % 16];
    if (k == 3) return rt::from_bits(u32());
    return static_cast<float>(static_cast<int32_t>(u32() % 20001u) - 10000) * 1e-3f;
  };
  long bad = 0;
  for (long i = 0; i < n; ++i) {
    RayIn ray;
    for (int k = 0; k < 3; ++k) {
      ray.o[k] = coord();
      ray.d[k] = u32() % 8 == 0 ? (u32() % 2 ? 0.0f : -0.0f) : coord();
    }
    ray.tmin = u32() % 2 ? 0.0f : coord();
    ray.tmax = u32() % 2 ? rt::kInf : coord();
    ray.shadow = false;
    const Prepared p = prepare(ray);
    const Box4Ray v = box4_ray(p);
    NodeRec rec[4];
    for (NodeRec& r : rec) {
      r.word0 = r.word1 = 0;
      for (int k = 0; k < 3; ++k) {
        float a = coord(), b = coord();
        if (u32() % 4 != 0 && a > b) std::swap(a, b);  // mostly valid boxes, some inverted
        if (u32() % 8 == 0) b = a;                      // flat boxes
        r.bmin[k] = a;
        r.bmax[k] = b;
      }
    }
    const float tmax = u32() % 2 ? ray.tmax : coord();
    float near4[4];
    const unsigned hit4 = box_test4(p, v, tmax, rec, near4);
    for (int s = 0; s < 4; ++s) {
      float near;
      const bool hit = box_test(p, tmax, rec[s], &near);
      if (hit != ((hit4 >> s & 1u) != 0) || rt::bits(near) != rt::bits(near4[s])) {
        if (++bad <= 10)
          std::printf("box4_selfcheck: case %ld slot %d: scalar hit %d near %a, SIMD hit %u near %a\n", i, s, hit, near, hit4 >> s & 1u,
                      near4[s]);
      }
    }
  }
  return bad;
#else
  (void)seed;
  (void)n;
  return -1;
#endif
}
#ifdef RTG_BOX4
#pragma GCC diagnostic pop
#endif

HitOut trace(const Image& img, const RayIn& ray, const WalkConfig& cfg, WalkStats* stats) {
  const Prepared p = prepare(ray);
  const int slots = img.slots();
#ifdef RTG_BOX4
  const bool box4 = slots % 4 == 0;
  const Box4Ray v4 = box4_ray(p);
#endif
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
#ifdef RTG_BOX4
      unsigned hit4[2] = {0, 0};
      float near4[8];
      if (box4)
        for (int g = 0; g < slots / 4; ++g) hit4[g] = box_test4(p, v4, tmax, rec + 4 * g, near4 + 4 * g);
#endif
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
#ifdef RTG_BOX4
        if (box4) {
          if (hit4[s / 4] >> (s % 4) & 1u) hits[nh++] = Hit{near4[s], s};
          continue;
        }
#endif
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
