// Closed test mesh for the leak test: a subdivided icosahedron whose vertices
// are moved radially by a seeded random factor (in the spirit of pbrt's
// watertightness test), then offset and rounded to FP32. Vertices are shared
// by index, so the FP32 mesh is closed whatever the rounding does.
#pragma once
#include <array>
#include <vector>

#include "rng.h"

namespace rt {

struct ClosedMesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<int, 3>> faces;       // outward winding
  std::vector<std::array<int, 2>> edges;       // each undirected edge once
  std::vector<std::array<int, 2>> edge_faces;  // the two faces on each edge
};

// level 0 = icosahedron (20 faces); each level multiplies faces by 4.
// Throws std::runtime_error if an edge does not have exactly two faces.
ClosedMesh make_perturbed_icosphere(int level, double radius, double offset, Rng& rng);

}  // namespace rt
