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
//     A ray the golden walk flags (error bits) must make rayIntersect throw
//     (RTACCEL_ON_ERROR's default), never answer a silent miss.
//   dropin-check --rtl <package dir> <rays> <threads>   the drop-in in rtl
//     mode (librtaccel's simulation; only in the build that links it,
//     dropin-check-rtl) against golden mode, hit for hit: the package's first
//     <rays> rays (every third one as a shadow ray) plus two invalid rays,
//     asked from <threads> threads at once of the rtl Accel, every answer
//     (return value, its bit for bit, mesh, or the thrown message) equal to
//     golden mode's answer to the same ray; with several threads, the median
//     batch sent to the hardware must hold more than one ray.
//   dropin-check --bench <package dir> [threads]   golden-mode throughput.
#include <nori/accel.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <unistd.h>

#include "nori-accel/golden/package_io.h"
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

// One answer of rayIntersect: the return value, its, or what it threw.
struct Answer {
  bool hit = false;
  Intersection its;
  std::string thrown;
};

Answer ask(const Accel& accel, const rtg::RayIn& r) {
  Answer a;
  a.its.t = -1.0f;  // a sentinel: shadow rays must leave its alone
  try {
    a.hit = accel.rayIntersect(Ray3f(Point3f(r.o[0], r.o[1], r.o[2]), Vector3f(r.d[0], r.d[1], r.d[2]), r.tmin, r.tmax), a.its, r.shadow);
  } catch (const std::runtime_error& e) {
    a.thrown = e.what();
  }
  return a;
}

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
    const Answer a = ask(accel, r);
    const bool got = a.hit;
    const Intersection& its = a.its;
    const std::string& thrown = a.thrown;
    std::string why;
    if (g.errors != 0 || !thrown.empty()) {
      if (g.errors == 0) why = "threw '" + thrown + "' for an unflagged ray";
      else if (thrown.empty()) why = "answered a ray the hardware flags (errors " + std::to_string(g.errors) + ") without throwing";
    } else if (got != g.hit) why = "hit " + std::to_string(got) + ", golden " + std::to_string(g.hit);
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
      // Eigen's cross product, written out (Eigen/src/Geometry/OrthoMethods.h's
      // order) so that this file needs no <Eigen/Geometry>: the link of
      // accel.cpp's cross() must come from accel.cpp's own include (stub common.h).
      const Vector3f e1 = p1 - p0, e2 = p2 - p0;
      const Vector3f n = Vector3f(e1.y() * e2.z() - e1.z() * e2.y(), e1.z() * e2.x() - e1.x() * e2.z(),
                                  e1.x() * e2.y() - e1.y() * e2.x()).normalized();
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

// RTACCEL_ON_ERROR=warn: a flagged ray (NaN direction) is answered a miss
// without throwing (and reported on stderr), its untouched; the default
// (throw) is checked on every flagged ray by check() and rtlCheck().
int warnCheck(const std::string& dir) {
  const char* rec = std::getenv("RTACCEL_RECORD");
  const std::string record = rec ? rec : "";  // this ray is not one to record
  unsetenv("RTACCEL_RECORD");
  setenv("RTACCEL_ON_ERROR", "warn", 1);
  Loaded pkg(dir);
  unsetenv("RTACCEL_ON_ERROR");
  if (!record.empty()) setenv("RTACCEL_RECORD", record.c_str(), 1);
  rtg::RayIn r = pkg.rays.at(0);
  r.d[0] = std::nanf("");
  r.shadow = false;
  const Answer a = ask(pkg.accel, r);
  const bool ok = a.thrown.empty() && !a.hit && a.its.t == -1.0f;
  std::printf("dropin-check: RTACCEL_ON_ERROR=warn: a NaN-direction ray %s\n",
              ok ? "is answered a reported miss" : ("gave hit " + std::to_string(a.hit) + ", thrown '" + a.thrown + "'").c_str());
  return ok ? 0 : 1;
}

// build() with a nori-bridge that fails: it throws with the tool's output in
// the message and leaves nothing in $TMPDIR; with RTACCEL_KEEP_TMP=1 it keeps
// its directory (scene, meshes, compile.log) for the user to look at.
int cleanupCheck(const std::string& dir) {
  const rtg::Image img = rtg::read_image(dir + "/image.bin");
  const Scene s = meshes_of(img);
  const std::filesystem::path tmp = std::filesystem::temp_directory_path() /
                                    ("dropin-check-tmp-" + std::to_string(static_cast<long>(getpid())));
  std::filesystem::remove_all(tmp);
  std::filesystem::create_directories(tmp);
  const char* oldTmp = std::getenv("TMPDIR");
  const std::string savedTmp = oldTmp ? oldTmp : "";
  setenv("TMPDIR", tmp.c_str(), 1);
  setenv("RTACCEL_NORI_BRIDGE", "/bin/false", 1);  // a nori-bridge that fails
  auto attempt = [&](bool keep) {
    if (keep) setenv("RTACCEL_KEEP_TMP", "1", 1);
    Accel accel;
    for (const auto& m : s.meshes) accel.addMesh(m.get());
    std::string thrown;
    try {
      accel.build();
    } catch (const std::runtime_error& e) {
      thrown = e.what();
    }
    unsetenv("RTACCEL_KEEP_TMP");
    const auto left = std::distance(std::filesystem::directory_iterator(tmp), std::filesystem::directory_iterator());
    return std::make_pair(thrown, static_cast<long>(left));
  };
  const auto [thrownGone, leftGone] = attempt(false);
  const auto [thrownKept, leftKept] = attempt(true);
  unsetenv("RTACCEL_NORI_BRIDGE");
  if (savedTmp.empty()) unsetenv("TMPDIR"); else setenv("TMPDIR", savedTmp.c_str(), 1);
  std::filesystem::remove_all(tmp);
  std::string why;
  if (thrownGone.find("failed") == std::string::npos) why = "build() did not throw for a failing nori-bridge ('" + thrownGone + "')";
  else if (leftGone != 0) why = "build() left " + std::to_string(leftGone) + " entries in TMPDIR after failing";
  else if (thrownKept.find("compile.log") == std::string::npos || leftKept != 1)
    why = "RTACCEL_KEEP_TMP=1: " + std::to_string(leftKept) + " directories kept, message '" + thrownKept + "'";
  std::printf("dropin-check: build() with a failing nori-bridge %s\n",
              why.empty() ? "throws and removes its directory (kept with RTACCEL_KEEP_TMP=1)" : why.c_str());
  return why.empty() ? 0 : 1;
}

bool sameFrame(const Frame& a, const Frame& b) { return same3(a.n, b.n) && same3(a.s, b.s) && same3(a.t, b.t); }

// Which part of two answers differs ("" if none), meshes compared by their index in each scene.
std::string differs(const Answer& a, const Scene& sa, const Answer& b, const Scene& sb) {
  if (a.thrown != b.thrown) return "thrown '" + a.thrown + "' vs '" + b.thrown + "'";
  if (a.hit != b.hit) return "hit " + std::to_string(a.hit) + " vs " + std::to_string(b.hit);
  auto meshIndex = [](const Scene& s, const Mesh* m) {
    for (size_t k = 0; k < s.meshes.size(); ++k) if (s.meshes[k].get() == m) return static_cast<long>(k);
    return -1L;
  };
  if (!same(a.its.t, b.its.t)) return "t";
  if (!same(a.its.uv.x(), b.its.uv.x()) || !same(a.its.uv.y(), b.its.uv.y())) return "uv";
  if (!same3(a.its.p, b.its.p)) return "p";
  if (!sameFrame(a.its.geoFrame, b.its.geoFrame) || !sameFrame(a.its.shFrame, b.its.shFrame)) return "frames";
  if (meshIndex(sa, a.its.mesh) != meshIndex(sb, b.its.mesh)) return "mesh";
  return "";
}

int rtlCheck(const std::string& dir, size_t count, unsigned threads) {
  setenv("RTACCEL_MODE", "golden", 1);
  Loaded golden(dir);
  setenv("RTACCEL_MODE", "rtl", 1);
  Loaded rtl(dir);
  std::vector<rtg::RayIn> rays(golden.rays.begin(), golden.rays.begin() + static_cast<long>(std::min(count, golden.rays.size())));
  for (size_t i = 2; i < rays.size(); i += 3) rays[i].shadow = true;
  // Two rays the hardware flags (invalid ray): a NaN direction and a zero direction.
  rtg::RayIn bad = rays.at(0);
  bad.d[1] = std::nanf("");
  rays.push_back(bad);
  bad.d[0] = bad.d[1] = bad.d[2] = 0.0f;
  rays.push_back(bad);
  std::vector<Answer> got(rays.size());
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      for (size_t i = k; i < rays.size(); i += threads) got[i] = ask(rtl.accel, rays[i]);
    });
  for (auto& t : pool) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  long bad_rays = 0, hits = 0, flagged = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Answer want = ask(golden.accel, rays[i]);
    hits += want.hit;
    flagged += !want.thrown.empty();
    const std::string why = differs(got[i], rtl.s, want, golden.s);
    if (!why.empty() && ++bad_rays <= 10)
      std::printf("dropin-check --rtl: %s: ray %zu%s: rtl mode and golden mode differ: %s\n", dir.c_str(), i,
                  rays[i].shadow ? " (shadow)" : "", why.c_str());
  }
  if (flagged != 2) {
    std::printf("dropin-check --rtl: %ld rays threw in golden mode, expected the 2 invalid rays\n", flagged);
    ++bad_rays;
  }
  // Batching across threads: with one ray from each of several threads in a
  // batch, the median batch holds more than one ray. Nothing here depends on
  // the machine's speed as long as RTACCEL_RTL_WINDOW_US outlasts a thread's
  // time between two rays (the make target sets a long window: a batch closes
  // as soon as every thread has a ray in it, so the window is only spent
  // when a thread finishes).
  const uint32_t median = rtl.accel.rtlMedianBatch();
  std::printf("dropin-check --rtl: %s: batches: median %u rays; sizes (rays x batches): %s\n", dir.c_str(), median,
              rtl.accel.rtlBatchHistogram().c_str());
  if (threads > 1 && median <= 1) {
    std::printf("dropin-check --rtl: %u threads, yet the median batch holds %u ray: rays are not gathered across threads "
                "(is RTACCEL_RTL_WINDOW_US=%s long enough?)\n", threads, median,
                std::getenv("RTACCEL_RTL_WINDOW_US") ? std::getenv("RTACCEL_RTL_WINDOW_US") : "<default>");
    ++bad_rays;
  }
  std::printf("dropin-check --rtl: %s: %zu rays (%ld hits, %ld flagged) from %u threads through the rtl mode in %.1f s wall, "
              "%ld differ from golden mode\n", dir.c_str(), rays.size(), hits, flagged, threads, wall, bad_rays);
  return bad_rays == 0 ? 0 : 1;
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
    if (argc == 5 && std::strcmp(argv[1], "--rtl") == 0)
      return rtlCheck(argv[2], std::strtoul(argv[3], nullptr, 10), static_cast<unsigned>(std::atoi(argv[4])));
    if (argc < 2 || argv[1][0] == '-') {
      std::fprintf(stderr, "usage: dropin-check <package dir>... | --rtl <package dir> <rays> <threads> | --bench <package dir> [threads]\n");
      return 2;
    }
    int rc = warnCheck(argv[1]) | cleanupCheck(argv[1]);
    for (int i = 1; i < argc; ++i) rc |= check(argv[i]);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Error: %s\n", e.what());
    return 1;
  }
}
