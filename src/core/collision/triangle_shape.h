// A triangle mesh as a collider's surface: closest-point queries through a bounding-volume
// hierarchy, and the sign of a closed mesh's distance from angle-weighted pseudo-normals
// (Bærentzen & Aanæs 2005, "Signed distance computation using the angle weighted
// pseudonormal"): the closest point's feature (face, edge or vertex) has a pseudo-normal whose
// side the query point lies on exactly when it is outside.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drape/math.h"
#include "drape/mesh.h"

namespace drape {

/// Edge u–v's key in a hash map, the same whichever way the edge is passed.
inline uint64_t edge_key(int32_t u, int32_t v) {
  return (uint64_t(uint32_t(std::min(u, v))) << 32) | uint32_t(std::max(u, v));
}

class TriangleShape {
 public:
  /// The triangles over `vertices` (m). A mesh whose every edge joins exactly two triangles is
  /// closed and has an inside (its triangles are turned to face out if they face in); any
  /// other is open and two-sided. Degenerate triangles (zero area) are dropped.
  TriangleShape(std::vector<Vec3> vertices, const std::vector<Triangle>& triangles);

  /// Distance from p to the surface, negative inside a closed mesh, and the outward normal
  /// there: the direction from the closest point to p (for a point on the surface, its
  /// pseudo-normal; on an open mesh, the side p is on).
  double signed_distance(const Vec3& p, Vec3& normal) const;

  /// Whether segment a–b passes through a triangle (segment_crosses_triangle).
  bool crossed_by(const Vec3& a, const Vec3& b) const;
  /// The triangle segment a–b passes through nearest a, or −1 where it passes through none.
  int32_t first_crossing(const Vec3& a, const Vec3& b) const;

  bool closed() const { return closed_; }
  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  /// Per triangle, its unit normal (outward on a closed mesh).
  const std::vector<Vec3>& face_normals() const { return face_normal_; }
  /// Per vertex, the sum of its triangles' normals weighted by their angles there (not unit).
  const std::vector<Vec3>& vertex_normals() const { return vertex_normal_; }
  /// The smallest axis-aligned box around the vertices.
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  int64_t bytes() const;

 private:
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< box around the node's triangles
    int32_t first = 0;  ///< leaf: first index into order_; inner: the right child
    int32_t count = 0;  ///< leaf: triangle count; 0 for an inner node (left child is next)
  };
  int32_t build(int32_t begin, int32_t end, std::vector<Vec3>& centroids);
  /// Calls f(triangle, along) for each triangle segment a–b passes through, `along` where the
  /// segment meets its plane (0 at a, 1 at b), until f returns true.
  template <class F>
  void each_crossing(const Vec3& a, const Vec3& b, F&& f) const;
  void closest(const Vec3& p, double& best2, int32_t& tri, Vec3& point, int& feature) const;
  Vec3 pseudo_normal(int32_t tri, int feature) const;

  std::vector<Vec3> vertices_;
  std::vector<Triangle> triangles_;
  std::vector<Vec3> face_normal_;    ///< unit, per triangle
  std::vector<Vec3> vertex_normal_;  ///< angle-weighted, per vertex
  std::vector<Vec3> edge_normal_;    ///< per triangle and edge (v0v1, v1v2, v2v0): both faces
  std::vector<Node> nodes_;
  std::vector<int32_t> order_;  ///< triangle indices, leaves' ranges
  bool closed_ = false;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();
};

}  // namespace drape
