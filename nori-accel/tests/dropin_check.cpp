// The Nori drop-in (include/nori/accel.h, src/accel.cpp) through Nori's
// interface, compiled against our stand-in Nori headers (stub/include).
//
//   dropin-check <package dir>...   every ray of each package through
//     Accel::rayIntersect, against the golden walk on the package's own
//     image.bin (which NoriAccelGoldenSpec proves bit-exact with the RTL's
//     golden model): hit, t, uv, mesh, p and geoFrame bit for bit, shadow
//     rays' occlusion with `its` untouched. The package's triangles are
//     handed over as three meshes (prim ranges), so several meshes and the
//     prim -> (mesh, face) mapping are exercised. The drop-in builds its own
//     4-wide image through nori-bridge from those meshes; on 4-wide packages
//     equal answers mean the same tree (visiting order decides ties), on the
//     other layouts they show the layouts agree on these rays.
//   dropin-check --bench <package dir> [threads]   golden-mode throughput.
#include <nori/accel.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <thread>

#include "../golden/package_io.h"
#include "../../hls/fp32.h"

using namespace nori;

namespace {
struct Scene {
  std::vector<std::unique_ptr<Mesh>> meshes;
  std::vector<size_t> first;  // prim of each mesh's first face
};

// The image's triangles by prim, as three meshes of unshared vertices.
Scene meshes_of(const rtg::Image& img) {
  std::vector<const rtg::TriRec*> byPrim(img.tris.size());
  for (const auto& t : img.tris) byPrim.at(t.prim) = &t;
  Scene s;
  const size_t n = byPrim.size(), parts = n >= 3 ? 3 : 1;
  for (size_t k = 0; k < parts; ++k) {
    const size_t a = n * k / parts, b = n * (k + 1) / parts;
    MatrixXf V(3, static_cast<int64_t>(3 * (b - a)));
    MatrixXu F(3, static_cast<int64_t>(b - a));
    for (size_t i = a; i < b; ++i)
      for (int c = 0; c < 3; ++c) {
        const int64_t col = static_cast<int64_t>(3 * (i - a) + c);
        for (int r = 0; r < 3; ++r) V(r, col) = byPrim[i]->v[c][r];
        F(c, static_cast<int64_t>(i - a)) = static_cast<uint32_t>(col);
      }
    auto m = std::make_unique<Mesh>();
    m->set(V, F, "part" + std::to_string(k));
    s.meshes.push_back(std::move(m));
    s.first.push_back(a);
  }
  return s;
}

bool same(float a, float b) { return rt::bits(a) == rt::bits(b); }
bool same3(const Vector3f& a, const Vector3f& b) { return same(a.x(), b.x()) && same(a.y(), b.y()) && same(a.z(), b.z()); }

// A package's image and rays, and a drop-in built over its triangles split into meshes.
struct Loaded {
  rtg::Image img;
  std::vector<rtg::RayIn> rays;
  Scene s;
  Accel accel;
  explicit Loaded(const std::string& dir)
      : img(rtg::read_image(dir + "/image.bin")), rays(rtg::read_rays_csv(dir + "/rays.csv")), s(meshes_of(img)) {
    for (auto& m : s.meshes) accel.addMesh(m.get());
    accel.build();
  }
};

int check(const std::string& dir) {
  Loaded pkg(dir);
  const rtg::Image& img = pkg.img;
  const std::vector<rtg::RayIn>& rays = pkg.rays;
  Scene& s = pkg.s;
  Accel& accel = pkg.accel;
  const rtg::WalkConfig cfg;
  long bad = 0, hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const rtg::RayIn& r = rays[i];
    const rtg::HitOut g = rtg::trace(img, r, cfg);
    Ray3f ray(Point3f(r.o[0], r.o[1], r.o[2]), Vector3f(r.d[0], r.d[1], r.d[2]), r.tmin, r.tmax);
    Intersection its;
    its.t = -1.0f;  // a sentinel: shadow rays must leave its alone
    const bool got = accel.rayIntersect(ray, its, r.shadow);
    std::string why;
    if (got != g.hit) why = "hit " + std::to_string(got) + ", golden " + std::to_string(g.hit);
    else if (r.shadow && its.t != -1.0f) why = "shadow ray wrote its";
    else if (got && !r.shadow) {
      ++hits;
      size_t k = s.first.size() - 1;
      while (s.first[k] > static_cast<size_t>(g.prim)) --k;
      const rtg::TriRec* tri = nullptr;
      for (const auto& t : img.tris) if (t.prim == g.prim) tri = &t;
      const Point3f p0(tri->v[0][0], tri->v[0][1], tri->v[0][2]), p1(tri->v[1][0], tri->v[1][1], tri->v[1][2]),
          p2(tri->v[2][0], tri->v[2][1], tri->v[2][2]);
      const float b0 = 1 - (g.u + g.v);
      const Point3f p = b0 * p0 + g.u * p1 + g.v * p2;
      const Vector3f n = (p1 - p0).cross(p2 - p0).normalized();
      if (!same(its.t, g.t)) why = "t";
      else if (!same(its.uv.x(), g.u) || !same(its.uv.y(), g.v)) why = "uv";
      else if (its.mesh != s.meshes[k].get()) why = "mesh";
      else if (!same3(its.p, p)) why = "p";
      else if (!same3(its.geoFrame.n, n) || !same3(its.shFrame.n, n)) why = "frames";
    }
    if (!why.empty() && ++bad <= 10) std::printf("dropin-check: %s: ray %zu: %s differs from the golden walk\n", dir.c_str(), i, why.c_str());
  }
  std::printf("dropin-check: %s: %zu rays (%ld hits) through Accel::rayIntersect, %ld differ from the golden walk\n", dir.c_str(),
              rays.size(), hits, bad);
  return bad == 0 ? 0 : 1;
}

double thread_cpu() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Golden-mode throughput: every thread asks rayIntersect for the package's
// rays, repeated to at least 2M rays in all. Wall-clock rays/s on a shared
// machine depend on its load, so CPU-seconds are reported beside them.
int bench(const std::string& dir, unsigned threads) {
  Loaded pkg(dir);
  const std::vector<rtg::RayIn>& rays = pkg.rays;
  Accel& accel = pkg.accel;
  const size_t per = std::max<size_t>(rays.size(), 2000000 / threads);
  std::vector<double> cpu(threads);
  std::vector<long> found(threads);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      const double c0 = thread_cpu();
      long n = 0;
      for (size_t i = 0; i < per; ++i) {
        const rtg::RayIn& r = rays[(i + k * 7919) % rays.size()];
        Intersection its;
        n += accel.rayIntersect(Ray3f(Point3f(r.o[0], r.o[1], r.o[2]), Vector3f(r.d[0], r.d[1], r.d[2]), r.tmin, r.tmax), its, r.shadow);
      }
      cpu[k] = thread_cpu() - c0;
      found[k] = n;
    });
  for (auto& t : pool) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double cpu_total = 0;
  for (double c : cpu) cpu_total += c;
  const double total = static_cast<double>(per) * threads;
  std::printf("{\"package\": \"%s\", \"threads\": %u, \"rays\": %.0f, \"wall_s\": %.3f, \"cpu_s\": %.3f, "
              "\"mrays_per_s_wall\": %.3f, \"mrays_per_cpu_s\": %.3f, \"mrays_per_s_at_%u_free_cores\": %.3f}\n",
              dir.c_str(), threads, total, wall, cpu_total, total / wall / 1e6, total / cpu_total / 1e6, threads,
              threads * total / cpu_total / 1e6);
  return found[0] >= 0 ? 0 : 1;
}
}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 3 && std::strcmp(argv[1], "--bench") == 0)
      return bench(argv[2], argc >= 4 ? static_cast<unsigned>(std::atoi(argv[3])) : 2u);
    if (argc < 2) { std::fprintf(stderr, "usage: dropin-check <package dir>... | --bench <package dir> [threads]\n"); return 2; }
    int rc = 0;
    for (int i = 1; i < argc; ++i) rc |= check(argv[i]);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Error: %s\n", e.what());
    return 1;
  }
}
