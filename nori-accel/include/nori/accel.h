// rtaccel's drop-in for Nori's include/nori/accel.h (written for rtaccel; no
// Nori code). Same public interface as Nori's Accel, so replacing Nori's
// accel.h and src/accel.cpp with nori-accel's is the whole integration; see
// docs/nori-dropin.md. Several meshes are supported (Nori's skeleton takes one).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nori/mesh.h>

NORI_NAMESPACE_BEGIN

struct RtAccelState;  // the memory image, triangle table and mode (src/accel.cpp)

class Accel {
public:
    Accel();
    ~Accel();

    /// Register a triangle mesh; only before build().
    void addMesh(Mesh *mesh);

    /// Build the BVH and memory image the way nori-bridge does (its own
    /// builder and layout: `nori-bridge compile --bvh 4`).
    void build();

    /// Return an axis-aligned box that bounds the scene
    const BoundingBox3f &getBoundingBox() const { return m_bbox; }

    /// Closest hit in [ray.mint, ray.maxt] (shadowRay: any hit, its untouched),
    /// as the FP32 accelerator answers it; fills its like Nori's own Accel.
    bool rayIntersect(const Ray3f &ray, Intersection &its, bool shadowRay) const;

    // Beyond Nori's interface (Nori never calls them): the rtl mode's batches
    // so far; 0 and "" in golden mode. ~Accel prints both to stderr.
    /// The median rays per batch sent to the simulated hardware.
    uint32_t rtlMedianBatch() const;
    /// Each batch size and how many batches had it, e.g. "1 x3, 2 x120".
    std::string rtlBatchHistogram() const;

private:
    std::vector<Mesh *> m_meshes;          ///< Meshes in addMesh order (prim numbering order)
    BoundingBox3f m_bbox;                  ///< Bounding box of the entire scene
    std::unique_ptr<RtAccelState> m_state; ///< Built by build()
};

NORI_NAMESPACE_END
