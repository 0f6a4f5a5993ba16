// C-simulation test bench of BboxIntersect: the hard cases of
// testdata/kernels/bbox_hard.txt, then RT_RANDOM seeded random cases. Writes
// every input and output to build/vectors/bbox.out (format: docs/kernels.md).
#include <cmath>
#include <exception>
#include <string>
#include <utility>

#include "bbox_intersect.h"
#include "case_gen.h"
#include "case_io.h"
#include "ray_setup.h"
#include "ref_f64.h"
#include "tb_common.h"

using namespace rt;

namespace {

// Independent transcription of the seed's control flow (compare-and-swap
// ordering, early exit), valid when no plane distance is NaN and the box is
// not empty. The kernel orders by the sign of d instead; both must agree.
bool seed_style_hit(const Ray& r, const BoxCase& c, float& near_out, bool& has_nan) {
  float near = -kInf, far = kInf;
  has_nan = false;
  for (int i = 0; i < 3; ++i) {
    if (r.d[i] == 0.0f) {
      if (r.o[i] < c.bmin[i] || r.o[i] > c.bmax[i]) return false;
      continue;
    }
    float t1 = (c.bmin[i] - r.o[i]) * r.rcp[i];
    float t2 = (c.bmax[i] - r.o[i]) * r.rcp[i];
    has_nan = has_nan || std::isnan(t1) || std::isnan(t2);
    if (t1 > t2) std::swap(t1, t2);
    near = t1 > near ? t1 : near;
    far = t2 < far ? t2 : far;
    near_out = near;
    if (!(near <= far)) return false;
  }
  near_out = near;
  return r.tmin <= far && near <= r.tmax;
}

bool input_has_nonfinite(const BoxCase& c) {
  bool bad = std::isnan(c.tmin) || std::isnan(c.tmax);
  for (int i = 0; i < 3; ++i) bad = bad || !std::isfinite(c.o[i]) || !std::isfinite(c.d[i]);
  return bad;
}

}  // namespace

int main() {
  const uint64_t seed = test_seed(std::getenv("RT_SEED"), kDefaultSeed);
  const long n_random = random_count();
  std::printf("tb_bbox: seed 0x%llx, %ld random cases\n", static_cast<unsigned long long>(seed), n_random);
  Failures fail(seed);
  Tally tally;
  try {
    std::vector<BoxCase> cases = read_box_cases(testdata_dir() + "/bbox_hard.txt");
    const size_t n_hard = cases.size();
    Rng rng(seed);
    for (long i = 0; i < n_random; ++i) cases.push_back(random_box_case(rng));
    FILE* out = open_or_throw(vectors_dir() + "/bbox.out", "w");
    std::fprintf(out, "# bbox.out: family o[3] d[3] tmin tmax bmin[3] bmax[3] rcp[3] : hit err near\n"
                      "# %zu hard cases, then %ld random cases from seed 0x%llx\n",
                 n_hard, n_random, static_cast<unsigned long long>(seed));
    for (size_t k = 0; k < cases.size(); ++k) {
      const BoxCase& c = cases[k];
      const Ray r = make_ray(c.o, c.d, c.tmin, c.tmax);
      BoxResult res;
      bbox_intersect(r.o, r.d, r.rcp, r.tmin, r.tmax, c.bmin, c.bmax, &res);
      std::fprintf(out, "%s %s %s %s : %d %d %s\n", box_inputs_line(c).c_str(), hex(r.rcp[0]).c_str(),
                   hex(r.rcp[1]).c_str(), hex(r.rcp[2]).c_str(), res.hit, res.err, hex(res.near).c_str());
      const std::string where = (k < n_hard ? "hard case " : "random case ") + std::to_string(k) + ": " +
                                box_inputs_line(c);
      const std::string& fam = c.family;
      tally.add(fam, "cases");
      if (res.hit) tally.add(fam, "hits");
      if (std::isnan(res.near)) fail.add("near is NaN, " + where);
      const bool nonfinite = input_has_nonfinite(c);
      if (res.err != ray_error(c.o, c.d, c.tmin, c.tmax) || (nonfinite && !res.err))
        fail.add("wrong error bit, " + where);
      if (res.err) {
        tally.add(fam, "err");
        if (res.hit) fail.add("error ray reported a hit, " + where);
        continue;
      }
      const BoxRef ref = box_ref_f64(c);
      if (ref.hit) tally.add(fam, "f64_hits");
      if (ref.hit && !res.hit) {
        if (ref.robust) {
          tally.add(fam, "miss_ROBUST");
          fail.add("false miss with f64 margin above the FP32 bound, " + where);
        } else {
          tally.add(fam, std::string("miss_") + ref.fragile);
        }
      }
      if (!ref.hit && res.hit) tally.add(fam, "false_hits");
      bool valid = true;
      for (int i = 0; i < 3; ++i) valid = valid && c.bmin[i] <= c.bmax[i];
      float seed_near = -kInf;
      bool has_nan = false;
      const bool seed_hit = seed_style_hit(r, c, seed_near, has_nan);
      if (valid && !has_nan) {
        tally.add(fam, "seed_checked");
        if (seed_hit != res.hit || (res.hit && !(seed_near == res.near)))
          fail.add("differs from the seed's compare-and-swap form, " + where);
      }
    }
    std::fclose(out);
  } catch (const std::exception& e) {
    std::printf("tb_bbox: error: %s\n", e.what());
    return 1;
  }
  tally.print("tb_bbox per family (miss_* = FP32 false misses vs f64, by reason; false_hits are allowed)");
  return fail.finish("tb_bbox");
}
