// Test stand-in (see common.h): Nori's Intersection and the Mesh accessors
// the drop-in uses (positions 3 x N, normals 3 x N or empty, texture
// coordinates 2 x N or empty, indices 3 x M), as Eigen matrices.
#pragma once
#include <nori/bbox.h>
#include <nori/frame.h>
#include <nori/ray.h>

NORI_NAMESPACE_BEGIN
struct Intersection {
  Point3f p;
  float t = 0;
  Point2f uv;
  Frame shFrame;
  Frame geoFrame;
  const Mesh* mesh = nullptr;
};

class Mesh {
 public:
  virtual ~Mesh() = default;
  uint32_t getTriangleCount() const { return static_cast<uint32_t>(m_F.cols()); }
  uint32_t getVertexCount() const { return static_cast<uint32_t>(m_V.cols()); }
  const BoundingBox3f& getBoundingBox() const { return m_bbox; }
  const MatrixXf& getVertexPositions() const { return m_V; }
  const MatrixXf& getVertexNormals() const { return m_N; }
  const MatrixXf& getVertexTexCoords() const { return m_UV; }
  const MatrixXu& getIndices() const { return m_F; }
  const std::string& getName() const { return m_name; }

  // Test-only setters (Nori's OBJ loader fills these in activate()).
  void set(const MatrixXf& V, const MatrixXu& F, const std::string& name) {
    m_V = V;
    m_F = F;
    m_name = name;
    m_bbox.reset();
    for (Eigen::Index j = 0; j < V.cols(); ++j) m_bbox.expandBy(Point3f(V.col(j)));
  }
  void setNormals(const MatrixXf& N) { m_N = N; }
  void setTexCoords(const MatrixXf& UV) { m_UV = UV; }

 protected:
  std::string m_name;
  MatrixXf m_V, m_N, m_UV;
  MatrixXu m_F;
  BoundingBox3f m_bbox;
};
NORI_NAMESPACE_END
