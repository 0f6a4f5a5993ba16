#include "closed_mesh.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace rt {

namespace {

using D3 = std::array<double, 3>;

D3 normalized(const D3& p) {
  const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return {p[0] / n, p[1] / n, p[2] / n};
}

// One midpoint vertex per edge, shared by both faces of the edge.
int midpoint(std::vector<D3>& v, std::map<std::pair<int, int>, int>& cache, int a, int b) {
  const auto key = std::make_pair(std::min(a, b), std::max(a, b));
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  v.push_back(normalized({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
  cache[key] = static_cast<int>(v.size()) - 1;
  return cache[key];
}

// How many faces contain the directed edge a -> b.
int directed_count(const std::vector<std::array<int, 3>>& f, int a, int b) {
  int n = 0;
  for (const auto& t : f)
    for (int k = 0; k < 3; ++k) n += t[k] == a && t[(k + 1) % 3] == b;
  return n;
}

}  // namespace

ClosedMesh make_perturbed_icosphere(int level, double radius, double offset, Rng& rng) {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<D3> v = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
                       {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (auto& p : v) p = normalized(p);
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> cache;
    std::vector<std::array<int, 3>> next;
    for (const auto& t : f) {
      const int ab = midpoint(v, cache, t[0], t[1]), bc = midpoint(v, cache, t[1], t[2]),
                ca = midpoint(v, cache, t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f.swap(next);
  }
  ClosedMesh m;
  for (const auto& p : v) {
    const double r = radius * rng.uniform(0.9, 1.1);  // radial perturbation, +-10%
    m.vertices.push_back({static_cast<float>(offset + r * p[0]), static_cast<float>(offset + r * p[1]),
                          static_cast<float>(offset + r * p[2])});
  }
  m.faces = f;
  std::map<std::pair<int, int>, std::vector<int>> edge_map;
  for (int i = 0; i < static_cast<int>(f.size()); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = f[i][k], b = f[i][(k + 1) % 3];
      edge_map[{std::min(a, b), std::max(a, b)}].push_back(i);
    }
  for (const auto& e : edge_map) {
    const bool two = e.second.size() == 2;
    if (two && directed_count(f, e.first.first, e.first.second) != 1)
      throw std::runtime_error("closed mesh: faces around edge " + std::to_string(e.first.first) + "-" +
                               std::to_string(e.first.second) + " are not consistently oriented");
    if (!two)
      throw std::runtime_error("closed mesh: edge " + std::to_string(e.first.first) + "-" +
                               std::to_string(e.first.second) + " has " + std::to_string(e.second.size()) +
                               " faces, expected 2");
    m.edges.push_back({e.first.first, e.first.second});
    m.edge_faces.push_back({e.second[0], e.second[1]});
  }
  return m;
}

}  // namespace rt
