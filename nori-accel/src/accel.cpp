// rtaccel's drop-in for Nori's src/accel.cpp (written for rtaccel; no Nori
// code). build() hands the meshes to nori-bridge, which builds the BVH and
// memory image exactly as for `make regress` (Embree's builder, 4-wide nodes);
// rayIntersect() asks the accelerator's golden model (golden/walk.h, bit-exact
// with the FP32 RTL) and fills the Intersection the way Nori's Accel does
// after a hit. Modes and recording: docs/nori-dropin.md.
#include <nori/accel.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <string>

#include "../golden/package_io.h"
#include "../golden/walk.h"

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
}  // namespace

/// Writes every ray asked for as a rays.txt line (`make regress RAYS=file`).
struct RayRecorder {
    std::mutex lock;
    std::ofstream out;
};

struct RtAccelState {
    rtg::Image image;
    rtg::WalkConfig config;
    std::vector<uint32_t> firstPrim;  ///< prim number of each mesh's first triangle
    std::unique_ptr<RayRecorder> recorder;
};

Accel::Accel() = default;
Accel::~Accel() = default;

void Accel::addMesh(Mesh *mesh) {
    if (m_state)
        throw std::runtime_error("Accel::addMesh() after build()");
    m_meshes.push_back(mesh);
    m_bbox.expandBy(mesh->getBoundingBox());
}

void Accel::build() {
    auto state = std::make_unique<RtAccelState>();
    const std::string mode = env("RTACCEL_MODE", "golden");
    if (mode == "rtl")
        throw std::runtime_error("RTACCEL_MODE=rtl needs librtaccel's simulation backend (issue 13), which is not built yet; "
                                 "use RTACCEL_MODE=golden, or record the rays (RTACCEL_RECORD=rays.txt) and replay them with make regress");
    if (mode != "golden")
        throw std::runtime_error("RTACCEL_MODE=" + mode + ": expected golden or rtl");
    if (m_meshes.empty())
        throw std::runtime_error("Accel::build(): no mesh was added");

    // The meshes as OBJ files (world-space vertices, shortest exact decimals)
    // and a Nori scene listing them in addMesh order, so prim numbers run
    // through the meshes in that order, faces in index order.
    char tmpl[] = "/tmp/nori-accel-XXXXXX";
    if (!mkdtemp(tmpl))
        throw std::runtime_error("Accel::build(): cannot create a temporary directory");
    const std::filesystem::path dir(tmpl);
    std::ofstream xml(dir / "scene.xml");
    xml << "<scene>\n";
    uint32_t prims = 0;
    for (size_t k = 0; k < m_meshes.size(); ++k) {
        const MatrixXf &V = m_meshes[k]->getVertexPositions();
        const MatrixXu &F = m_meshes[k]->getIndices();
        std::ofstream obj(dir / ("mesh" + std::to_string(k) + ".obj"));
        for (int64_t j = 0; j < V.cols(); ++j)
            obj << "v " << num(V(0, j)) << ' ' << num(V(1, j)) << ' ' << num(V(2, j)) << '\n';
        for (int64_t j = 0; j < F.cols(); ++j)
            obj << "f " << F(0, j) + 1 << ' ' << F(1, j) + 1 << ' ' << F(2, j) + 1 << '\n';
        xml << "  <mesh type=\"obj\"><string name=\"filename\" value=\"mesh" << k << ".obj\"/></mesh>\n";
        state->firstPrim.push_back(prims);
        prims += static_cast<uint32_t>(F.cols());
    }
    xml << "</scene>\n";
    xml.close();
    std::ofstream(dir / "one-ray.txt") << "0 0 0 0 0 1\n";  // compile wants a ray set; this one is not used
    const std::string bridge = env("RTACCEL_NORI_BRIDGE", NORI_ACCEL_BRIDGE);
    const std::string cmd = "'" + bridge + "' compile '" + (dir / "scene.xml").string() + "' --out '" + (dir / "pkg").string() +
                            "' --rays '" + (dir / "one-ray.txt").string() + "' --bvh 4 > '" + (dir / "compile.log").string() + "' 2>&1";
    if (std::system(cmd.c_str()) != 0)
        throw std::runtime_error("Accel::build(): `" + cmd + "` failed; see " + (dir / "compile.log").string() +
                                 " (set RTACCEL_NORI_BRIDGE to nori-bridge's path)");
    state->image = rtg::read_image((dir / "pkg" / "image.bin").string());
    if (state->image.tris.size() != prims)
        throw std::runtime_error("Accel::build(): the image holds " + std::to_string(state->image.tris.size()) +
                                 " triangles for " + std::to_string(prims));
    std::filesystem::remove_all(dir);

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
    // A ray the hardware flags (error bits) is answered as a miss, as the
    // accelerator's hit port reports it (hit = 0).
    const rtg::HitOut h = rtg::trace(m_state->image, r, m_state->config);
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
