// rtaccel's drop-in for Nori's src/accel.cpp (written for rtaccel; no Nori
// code). build() hands the meshes to nori-bridge, which builds the BVH and
// memory image exactly as for `make regress` (Embree's builder, 4-wide nodes);
// rayIntersect() asks the accelerator's golden model (golden/walk.h, bit-exact
// with the FP32 RTL) and fills the Intersection the way Nori's Accel does
// after a hit. In `rtl` mode the rays go through librtaccel's simulation
// instead (src/rtl_batcher.h). Modes, errors and recording: docs/nori-dropin.md.
#include <nori/accel.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <string>

// Every Eigen header this file uses, itself: Nori's common.h brings only
// <Eigen/Core>, which declares cross() but does not define it.
#include <Eigen/Core>
#include <Eigen/Geometry>

// Through the include path <the rtaccel checkout> (docs/nori-dropin.md), so
// they resolve wherever this file is copied, e.g. into Nori's src/.
#include "nori-accel/golden/package_io.h"
#include "nori-accel/golden/walk.h"
#ifdef RTACCEL_SIM
#include "nori-accel/src/rtl_batcher.h"
#endif

#ifndef NORI_ACCEL_BRIDGE
#define NORI_ACCEL_BRIDGE "nori-bridge"
#endif

NORI_NAMESPACE_BEGIN

namespace {
std::string num(float x) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);  // shortest exact decimal: reads back to x
    return std::string(buf, r.ptr);
}

std::string env(const char *name, const char *fallback) {
    const char *v = std::getenv(name);
    return v && *v ? v : fallback;
}

/// build()'s scratch directory under $TMPDIR (else /tmp): removed with
/// everything in it when build() returns or throws, unless `keep`.
struct TempDir {
    std::filesystem::path path;
    bool keep;
    explicit TempDir(bool keep_) : keep(keep_) {
        std::string tmpl = (std::filesystem::temp_directory_path() / "nori-accel-XXXXXX").string();
        if (!mkdtemp(tmpl.data()))
            throw std::runtime_error("Accel::build(): cannot create a temporary directory " + tmpl + ": " + std::strerror(errno));
        path = tmpl;
    }
    ~TempDir() {
        if (keep) {
            std::fprintf(stderr, "nori-accel: kept %s (RTACCEL_KEEP_TMP=1)\n", path.c_str());
            return;
        }
        std::error_code ec;  // a destructor must not throw; a leftover directory is only untidy
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir &) = delete;
    TempDir &operator=(const TempDir &) = delete;
};

/// The last `lines` lines of a text file, each ending in a newline ("" if unreadable).
std::string tail(const std::filesystem::path &file, size_t lines) {
    std::ifstream in(file);
    std::vector<std::string> last;
    for (std::string line; std::getline(in, line);) {
        last.push_back("  " + line + "\n");
        if (last.size() > lines)
            last.erase(last.begin());
    }
    std::string out;
    for (const std::string &l : last)
        out += l;
    return out;
}
}  // namespace

/// Writes every ray asked for as a rays.txt line (`make regress RAYS=file`).
struct RayRecorder {
    std::mutex lock;
    std::ofstream out;
};

/// What happens to a ray the hardware flags (HitOut.errors != 0): never a silent miss.
enum class OnError { Throw, Warn };

/// RTACCEL_ON_ERROR=warn: flagged rays are misses, each counted and the first
/// few printed to stderr; the total is printed when the Accel is destroyed.
struct ErrorLog {
    std::mutex lock;
    uint64_t count = 0;
    static constexpr uint64_t kPrinted = 10;
};

struct RtAccelState {
    rtg::Image image;
    rtg::WalkConfig config;
    std::vector<uint32_t> firstPrim;  ///< prim number of each mesh's first triangle
    std::unique_ptr<RayRecorder> recorder;
    OnError onError = OnError::Throw;
    ErrorLog errors;
#ifdef RTACCEL_SIM
    std::unique_ptr<nori_rtl::RtlBatcher> rtl;  ///< rtl mode: the simulated hardware answers
#endif
};

namespace {
const char *const kErrorNames[] = {"stack overflow", "index overflow", "leaf too big", "invalid ray", "bad scene data"};

std::string errorText(uint32_t bits) {
    std::string s;
    for (uint32_t b = 0; b < 32; ++b)
        if (bits >> b & 1)
            s += (s.empty() ? "" : ", ") + std::string(b < 5 ? kErrorNames[b] : "bit " + std::to_string(b));
    return s;
}

#ifdef RTACCEL_SIM
uint32_t envCount(const char *name, uint32_t fallback) {
    const std::string v = env(name, "");
    if (v.empty())
        return fallback;
    char *end = nullptr;
    const unsigned long x = std::strtoul(v.c_str(), &end, 10);
    if (*end != '\0' || x > 1000000)
        throw std::runtime_error(std::string(name) + "=" + v + ": expected a whole number up to 1000000");
    return static_cast<uint32_t>(x);
}
#endif
}  // namespace

Accel::Accel() = default;
Accel::~Accel() {
    if (!m_state)
        return;
#ifdef RTACCEL_SIM
    if (m_state->rtl) {
        const nori_rtl::BatchStats b = m_state->rtl->stats();
        std::fprintf(stderr,
                     "nori-accel rtl: %llu rays in %llu batches (median %u, largest %llu), %llu simulated cycles; "
                     "batch sizes (rays x batches): %s\n",
                     (unsigned long long)b.rays, (unsigned long long)b.batches, b.medianBatch(), (unsigned long long)b.largestBatch,
                     (unsigned long long)b.simCycles, b.histogram().c_str());
    }
#endif
    if (m_state->errors.count > 0)
        std::fprintf(stderr, "nori-accel: %llu rays were flagged by the hardware and answered as misses (RTACCEL_ON_ERROR=warn)\n",
                     (unsigned long long)m_state->errors.count);
}

uint32_t Accel::rtlMedianBatch() const {
#ifdef RTACCEL_SIM
    if (m_state && m_state->rtl)
        return m_state->rtl->stats().medianBatch();
#endif
    return 0;
}

std::string Accel::rtlBatchHistogram() const {
#ifdef RTACCEL_SIM
    if (m_state && m_state->rtl)
        return m_state->rtl->stats().histogram();
#endif
    return "";
}

void Accel::addMesh(Mesh *mesh) {
    if (m_state)
        throw std::runtime_error("Accel::addMesh() after build()");
    m_meshes.push_back(mesh);
    m_bbox.expandBy(mesh->getBoundingBox());
}

void Accel::build() {
    auto state = std::make_unique<RtAccelState>();
    const std::string mode = env("RTACCEL_MODE", "golden");
#ifndef RTACCEL_SIM
    if (mode == "rtl")
        throw std::runtime_error("RTACCEL_MODE=rtl: this build of the drop-in does not link librtaccel's simulation backend; "
                                 "build it with RTACCEL_SIM defined and the Verilated system linked (make -C nori-accel rtl SIMDIR=..., "
                                 "docs/nori-dropin.md), or use RTACCEL_MODE=golden");
#endif
    if (mode != "golden" && mode != "rtl")
        throw std::runtime_error("RTACCEL_MODE=" + mode + ": expected golden or rtl");
    const std::string onError = env("RTACCEL_ON_ERROR", "throw");
    if (onError != "throw" && onError != "warn")
        throw std::runtime_error("RTACCEL_ON_ERROR=" + onError + ": expected throw or warn");
    state->onError = onError == "warn" ? OnError::Warn : OnError::Throw;
    if (m_meshes.empty())
        throw std::runtime_error("Accel::build(): no mesh was added");

    // The meshes as OBJ files (world-space vertices, shortest exact decimals)
    // and a Nori scene listing them in addMesh order, so prim numbers run
    // through the meshes in that order, faces in index order. The directory
    // goes when build() returns or throws, unless RTACCEL_KEEP_TMP=1.
    const TempDir tmp(env("RTACCEL_KEEP_TMP", "0") == "1");
    const std::filesystem::path &dir = tmp.path;
    std::ofstream xml(dir / "scene.xml");
    xml << "<scene>\n";
    uint32_t prims = 0;
    for (size_t k = 0; k < m_meshes.size(); ++k) {
        const MatrixXf &V = m_meshes[k]->getVertexPositions();
        const MatrixXu &F = m_meshes[k]->getIndices();
        const std::filesystem::path objPath = dir / ("mesh" + std::to_string(k) + ".obj");
        std::ofstream obj(objPath);
        for (int64_t j = 0; j < V.cols(); ++j)
            obj << "v " << num(V(0, j)) << ' ' << num(V(1, j)) << ' ' << num(V(2, j)) << '\n';
        for (int64_t j = 0; j < F.cols(); ++j)
            obj << "f " << F(0, j) + 1 << ' ' << F(1, j) + 1 << ' ' << F(2, j) + 1 << '\n';
        obj.close();
        if (!obj)
            throw std::runtime_error("Accel::build(): cannot write " + objPath.string());
        xml << "  <mesh type=\"obj\"><string name=\"filename\" value=\"mesh" << k << ".obj\"/></mesh>\n";
        state->firstPrim.push_back(prims);
        prims += static_cast<uint32_t>(F.cols());
    }
    xml << "</scene>\n";
    xml.close();
    std::ofstream(dir / "one-ray.txt") << "0 0 0 0 0 1\n";  // compile wants a ray set; this one is not used
    if (!xml || !std::filesystem::exists(dir / "one-ray.txt"))
        throw std::runtime_error("Accel::build(): cannot write the scene into " + dir.string());
    const std::string bridge = env("RTACCEL_NORI_BRIDGE", NORI_ACCEL_BRIDGE);
    const std::filesystem::path log = dir / "compile.log";
    const std::string cmd = "'" + bridge + "' compile '" + (dir / "scene.xml").string() + "' --out '" + (dir / "pkg").string() +
                            "' --rays '" + (dir / "one-ray.txt").string() + "' --bvh 4 > '" + log.string() + "' 2>&1";
    if (std::system(cmd.c_str()) != 0)
        throw std::runtime_error("Accel::build(): `" + cmd + "` failed" +
                                 (tmp.keep ? "; see " + log.string() : " (RTACCEL_KEEP_TMP=1 keeps " + dir.string() + ")") +
                                 "; its output:\n" + tail(log, 20) +
                                 "set RTACCEL_NORI_BRIDGE to nori-bridge's path if it was not found (docs/nori-dropin.md)");
    const std::string imagePath = (dir / "pkg" / "image.bin").string();
    std::ifstream imageFile(imagePath, std::ios::binary);
    const std::vector<uint8_t> imageBytes((std::istreambuf_iterator<char>(imageFile)), std::istreambuf_iterator<char>());
    std::string err;
    if (!rtg::parse_image(imageBytes.data(), imageBytes.size(), state->image, err))
        throw std::runtime_error(imagePath + ": " + err);
    if (state->image.tris.size() != prims)
        throw std::runtime_error("Accel::build(): the image holds " + std::to_string(state->image.tris.size()) +
                                 " triangles for " + std::to_string(prims));
#ifdef RTACCEL_SIM
    if (mode == "rtl") {
        nori_rtl::BatchOptions opt;
        opt.maxBatch = envCount("RTACCEL_RTL_BATCH", opt.maxBatch);
        opt.windowUs = envCount("RTACCEL_RTL_WINDOW_US", opt.windowUs);
        state->rtl = std::make_unique<nori_rtl::RtlBatcher>(imageBytes, opt);
    }
#endif

    const std::string record = env("RTACCEL_RECORD", "");
    if (!record.empty()) {
        state->recorder = std::make_unique<RayRecorder>();
        state->recorder->out.open(record);
        if (!state->recorder->out)
            throw std::runtime_error("RTACCEL_RECORD=" + record + ": cannot write");
        state->recorder->out << "# rays asked of nori-accel's Accel, in call order: ox oy oz dx dy dz mint maxt "
                                "(replay: make regress SCENE=<scene.xml> RAYS=" << record << ")\n";
    }
    m_state = std::move(state);
}

bool Accel::rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const {
    if (!m_state)
        throw std::runtime_error("Accel::rayIntersect() before build()");
    rtg::RayIn r;
    for (int i = 0; i < 3; ++i) {
        r.o[i] = ray.o[i];
        r.d[i] = ray.d[i];
    }
    r.tmin = ray.mint;
    r.tmax = ray.maxt;
    r.shadow = shadowRay;
    if (RayRecorder *rec = m_state->recorder.get()) {
        std::lock_guard<std::mutex> g(rec->lock);
        rec->out << num(r.o[0]) << ' ' << num(r.o[1]) << ' ' << num(r.o[2]) << ' ' << num(r.d[0]) << ' ' << num(r.d[1]) << ' '
                 << num(r.d[2]) << ' ' << num(r.tmin) << ' ' << num(r.tmax) << (shadowRay ? " # shadow\n" : "\n");
    }
#ifdef RTACCEL_SIM
    const rtg::HitOut h = m_state->rtl ? m_state->rtl->trace(r) : rtg::trace(m_state->image, r, m_state->config);
#else
    const rtg::HitOut h = rtg::trace(m_state->image, r, m_state->config);
#endif
    // A ray the hardware flags (error bits; its hit bit is 0) is never a silent miss.
    if (h.errors != 0) {
        const std::string what = "nori-accel: the accelerator flagged the ray o=(" + num(r.o[0]) + ", " + num(r.o[1]) + ", " +
                                 num(r.o[2]) + ") d=(" + num(r.d[0]) + ", " + num(r.d[1]) + ", " + num(r.d[2]) + ") mint=" +
                                 num(r.tmin) + " maxt=" + num(r.tmax) + ": " + errorText(h.errors);
        if (m_state->onError == OnError::Throw)
            throw std::runtime_error(what + " (RTACCEL_ON_ERROR=warn answers such rays as misses, reported)");
        ErrorLog &log = m_state->errors;
        std::lock_guard<std::mutex> g(log.lock);
        if (++log.count <= ErrorLog::kPrinted)
            std::fprintf(stderr, "%s; answered as a miss%s\n", what.c_str(), log.count == ErrorLog::kPrinted ? " (no more printed)" : "");
        return false;
    }
    if (!h.hit)
        return false;
    if (shadowRay)
        return true;  // Nori's contract: its is left alone for shadow rays

    // The mesh and its face: prim numbers run through the meshes in addMesh order.
    const std::vector<uint32_t> &first = m_state->firstPrim;
    const size_t k = static_cast<size_t>(std::upper_bound(first.begin(), first.end(), static_cast<uint32_t>(h.prim)) - first.begin()) - 1;
    const Mesh *mesh = m_meshes[k];
    const uint32_t f = static_cast<uint32_t>(h.prim) - first[k];
    its.t = h.t;
    its.uv = Point2f(h.u, h.v);
    its.mesh = mesh;

    // From here as Nori's Accel does after a hit: barycentrics (1-u-v, u, v),
    // position from the vertices, texture coordinates if the mesh has them,
    // geometric frame from the face, shading frame from interpolated normals.
    const float b0 = 1 - its.uv.sum(), b1 = its.uv.x(), b2 = its.uv.y();
    const MatrixXf &V = mesh->getVertexPositions();
    const MatrixXf &N = mesh->getVertexNormals();
    const MatrixXf &UV = mesh->getVertexTexCoords();
    const MatrixXu &F = mesh->getIndices();
    const uint32_t i0 = F(0, f), i1 = F(1, f), i2 = F(2, f);
    const Point3f p0(V(0, i0), V(1, i0), V(2, i0)), p1(V(0, i1), V(1, i1), V(2, i1)), p2(V(0, i2), V(1, i2), V(2, i2));
    its.p = b0 * p0 + b1 * p1 + b2 * p2;
    if (UV.size() > 0)
        its.uv = Point2f(b0 * UV(0, i0) + b1 * UV(0, i1) + b2 * UV(0, i2), b0 * UV(1, i0) + b1 * UV(1, i1) + b2 * UV(1, i2));
    its.geoFrame = Frame((p1 - p0).cross(p2 - p0).normalized());
    if (N.size() > 0) {
        const Normal3f n0(N(0, i0), N(1, i0), N(2, i0)), n1(N(0, i1), N(1, i1), N(2, i1)), n2(N(0, i2), N(1, i2), N(2, i2));
        its.shFrame = Frame((b0 * n0 + b1 * n1 + b2 * n2).normalized());
    } else {
        its.shFrame = its.geoFrame;
    }
    return true;
}

NORI_NAMESPACE_END
