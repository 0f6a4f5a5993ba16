// C-simulation test bench of both PrimIntersect variants: the hard cases of
// testdata/kernels/tri_hard.txt, then RT_RANDOM seeded random cases. Writes
// build/vectors/prim_mt.out and prim_wt.out (format: docs/kernels.md).
#include <cmath>
#include <exception>
#include <string>

#include "case_gen.h"
#include "case_io.h"
#include "hard_groups.h"
#include "prim_mt.h"
#include "prim_wt.h"
#include "ref_f64.h"
#include "tb_common.h"

using namespace rt;

namespace {

// Nori's Mesh::rayIntersect transcribed with its early returns, Eigen's dot
// order written out. The kernel evaluates everything and decides at the end;
// on every case where Nori is defined the two must agree bit for bit.
bool nori_reference(const TriCase& c, float& u, float& v, float& t) {
  float e1[3], e2[3], tv[3];
  for (int i = 0; i < 3; ++i) { e1[i] = c.p1[i] - c.p0[i]; e2[i] = c.p2[i] - c.p0[i]; tv[i] = c.o[i] - c.p0[i]; }
  const float px = c.d[1] * e2[2] - c.d[2] * e2[1], py = c.d[2] * e2[0] - c.d[0] * e2[2],
              pz = c.d[0] * e2[1] - c.d[1] * e2[0];
  const float det = e1[0] * px + (e1[1] * py + e1[2] * pz);
  if (det > -1e-8f && det < 1e-8f) return false;
  const float inv_det = 1.0f / det;
  u = (tv[0] * px + (tv[1] * py + tv[2] * pz)) * inv_det;
  if (u < 0.0 || u > 1.0) return false;
  const float qx = tv[1] * e1[2] - tv[2] * e1[1], qy = tv[2] * e1[0] - tv[0] * e1[2],
              qz = tv[0] * e1[1] - tv[1] * e1[0];
  v = (c.d[0] * qx + (c.d[1] * qy + c.d[2] * qz)) * inv_det;
  if (v < 0.0 || u + v > 1.0) return false;
  t = (e2[0] * qx + (e2[1] * qy + e2[2] * qz)) * inv_det;
  return t >= c.tmin && t <= c.tmax;
}

bool nonfinite_ray(const TriCase& c) {
  bool bad = std::isnan(c.tmin) || std::isnan(c.tmax);
  for (int i = 0; i < 3; ++i) bad = bad || !std::isfinite(c.o[i]) || !std::isfinite(c.d[i]);
  return bad;
}

void write(FILE* f, const std::string& inputs, const PrimResult& r) {
  std::fprintf(f, "%s : %d %d %s %s %s\n", inputs.c_str(), r.hit, r.err, hex(r.t).c_str(), hex(r.u).c_str(),
               hex(r.v).c_str());
}

// Checks every variant must pass; `name` is "mt" or "wt".
void common_checks(const char* name, const TriCase& c, const PrimResult& r, const std::string& where,
                   Failures& fail) {
  const std::string n = name;
  if (std::isnan(r.t) || std::isnan(r.u) || std::isnan(r.v)) fail.add(n + ": NaN output, " + where);
  if (!r.hit && (bits(r.t) | bits(r.u) | bits(r.v)) != 0) fail.add(n + ": miss outputs are not +0, " + where);
  if (r.err != ray_error(c.o, c.d, c.tmin, c.tmax) || (nonfinite_ray(c) && !r.err))
    fail.add(n + ": wrong error bit, " + where);
  if (r.err && r.hit) fail.add(n + ": error ray reported a hit, " + where);
  if (coincident_vertices(c.p0, c.p1, c.p2) && r.hit) fail.add(n + ": zero-area triangle hit, " + where);
}

// Convention check with exact arithmetic: a triangle in the plane x[kz] = 2,
// p1 = p0 + 4 e_a, p2 = p0 + 4 e_b, ray along +-e_kz through
// p0 + 0.25 (p1 - p0) + 0.5 (p2 - p0). Every intermediate value is a small
// dyadic number, so both kernels must return exactly t = 2, u = 0.25 (weight
// of p1), v = 0.5 (weight of p2), for every axis and direction sign.
void check_uv_convention(Failures& fail) {
  for (int kz = 0; kz < 3; ++kz)
    for (float sgn : {1.0f, -1.0f}) {
      const int a = (kz + 1) % 3, b = (kz + 2) % 3;
      float p0[3] = {0.5f, 0.5f, 0.5f}, p1[3], p2[3], o[3], d[3] = {0, 0, 0};
      p0[kz] = 2.0f;
      for (int i = 0; i < 3; ++i) { p1[i] = p0[i]; p2[i] = p0[i]; o[i] = p0[i]; }
      p1[a] += 4.0f; p2[b] += 4.0f;
      o[a] += 1.0f; o[b] += 2.0f; o[kz] = sgn > 0 ? 0.0f : 4.0f;
      d[kz] = sgn;
      PrimResult mt, wt;
      prim_intersect_mt(o, d, 0.0f, kInf, p0, p1, p2, &mt);
      const RayShear s = make_shear(make_ray(o, d, 0.0f, kInf));
      prim_intersect_wt(o, d, 0.0f, kInf, s, p0, p1, p2, &wt);
      for (const PrimResult* r : {&mt, &wt})
        if (!r->hit || r->t != 2.0f || r->u != 0.25f || r->v != 0.5f)
          fail.add(std::string(r == &mt ? "mt" : "wt") + ": u/v convention check failed on axis " +
                   std::to_string(kz) + (sgn > 0 ? " +" : " -") + ": hit " + std::to_string(r->hit) + " t " +
                   std::to_string(r->t) + " u " + std::to_string(r->u) + " v " + std::to_string(r->v));
    }
}


}  // namespace

int main() {
  const uint64_t seed = test_seed(std::getenv("RT_SEED"), kDefaultSeed);
  const long n_random = random_count();
  std::printf("tb_prim: seed 0x%llx, %ld random cases\n", static_cast<unsigned long long>(seed), n_random);
  Failures fail(seed);
  Tally tally;
  check_uv_convention(fail);
  try {
    std::vector<TriCase> cases = read_tri_cases(testdata_dir() + "/tri_hard.txt");
    const size_t n_hard = cases.size();
    Rng rng(seed ^ 0x7e1a0000ull);  // a different stream from tb_bbox's
    for (long i = 0; i < n_random; ++i) cases.push_back(random_tri_case(rng));
    FILE* out_mt = open_or_throw(vectors_dir() + "/prim_mt.out", "w");
    FILE* out_wt = open_or_throw(vectors_dir() + "/prim_wt.out", "w");
    const char* head = "# %zu hard cases, then %ld random cases from seed 0x%llx\n";
    std::fprintf(out_mt, "# prim_mt.out: family o[3] d[3] tmin tmax p0[3] p1[3] p2[3] : hit err t u v\n");
    std::fprintf(out_wt, "# prim_wt.out: family o[3] d[3] tmin tmax p0[3] p1[3] p2[3] kx ky kz sx sy sz : hit err t u v\n");
    for (FILE* f : {out_mt, out_wt}) std::fprintf(f, head, n_hard, n_random, static_cast<unsigned long long>(seed));
    std::vector<bool> hits_mt, hits_wt;
    for (size_t k = 0; k < cases.size(); ++k) {
      const TriCase& c = cases[k];
      const std::string fam = c.family, inputs = tri_inputs_line(c);
      const std::string where = (k < n_hard ? "hard case " : "random case ") + std::to_string(k) + ": " + inputs;
      PrimResult mt, wt;
      prim_intersect_mt(c.o, c.d, c.tmin, c.tmax, c.p0, c.p1, c.p2, &mt);
      const RayShear s = make_shear(make_ray(c.o, c.d, c.tmin, c.tmax));
      prim_intersect_wt(c.o, c.d, c.tmin, c.tmax, s, c.p0, c.p1, c.p2, &wt);
      write(out_mt, inputs, mt);
      char shear[64];
      std::snprintf(shear, sizeof shear, " %d %d %d %s %s %s", s.kx, s.ky, s.kz, hex(s.sx).c_str(), hex(s.sy).c_str(),
                    hex(s.sz).c_str());
      write(out_wt, inputs + shear, wt);
      common_checks("mt", c, mt, where, fail);
      common_checks("wt", c, wt, where, fail);
      tally.add(fam, "cases");
      if (mt.err) tally.add(fam, "err");
      if (mt.hit) tally.add(fam, "mt_hits");
      if (wt.hit) tally.add(fam, "wt_hits");
      const bool ref = tri_ref_f64(c);
      if (ref) tally.add(fam, "f64_hits");
      if (mt.hit != ref) tally.add(fam, "mt_vs_f64");
      if (wt.hit != ref) tally.add(fam, "wt_vs_f64");
      if (mt.hit != wt.hit) tally.add(fam, "mt_vs_wt");
      float nu = 0, nv = 0, nt = 0;
      const bool nori = nori_reference(c, nu, nv, nt);
      const bool nori_defined = !mt.err && !coincident_vertices(c.p0, c.p1, c.p2) && !(nori && (std::isnan(nu) || std::isnan(nv)));
      if (nori_defined && (nori != mt.hit || (nori && (bits(nu) != bits(mt.u) || bits(nv) != bits(mt.v) || bits(nt) != bits(mt.t)))))
        fail.add("mt differs from Nori's rayIntersect, " + where);
      hits_mt.push_back(mt.hit);
      hits_wt.push_back(wt.hit);
    }
    for (const CaseGroup& g : shared_groups(cases, n_hard)) {
      bool mt_any = false, wt_any = false;
      for (size_t k = g.begin; k < g.end; ++k) { mt_any = mt_any || hits_mt[k]; wt_any = wt_any || hits_wt[k]; }
      tally.add(g.family, "groups");
      if (!mt_any) tally.add(g.family, "mt_leaks");
      if (!wt_any) {
        tally.add(g.family, "wt_leaks");
        fail.add("watertight leak: no triangle of the group hit, hard case " + std::to_string(g.begin) + ": " +
                 tri_inputs_line(cases[g.begin]));
      }
    }
    std::fclose(out_mt);
    std::fclose(out_wt);
  } catch (const std::exception& e) {
    std::printf("tb_prim: error: %s\n", e.what());
    return 1;
  }
  tally.print("tb_prim per family (*_vs_* = hit disagreements, counted not failed; *_leaks = groups with no hit)");
  return fail.finish("tb_prim");
}
