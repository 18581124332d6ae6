#include "collision/sharp_features.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <utility>

namespace drape {

SharpFeatures sharp_features(const TriangleShape& shape, double angle) {
  SharpFeatures out;
  const std::vector<Vec3>& vertices = shape.vertices();
  const std::vector<Triangle>& triangles = shape.triangles();
  const std::vector<Vec3>& face_normal = shape.face_normals();
  const std::vector<Vec3>& vertex_normal = shape.vertex_normals();
  const size_t nt = triangles.size();
  std::vector<std::vector<int32_t>> vertex_faces(vertices.size());
  for (size_t f = 0; f < nt; ++f)
    for (int32_t v : triangles[f]) vertex_faces[v].push_back(int32_t(f));
  // Edges: each met from its two faces; the one that meets it second adds it.
  const double cos_edge = std::cos(angle);
  std::unordered_map<uint64_t, int32_t> first_face;
  for (size_t f = 0; f < nt; ++f)
    for (int e = 0; e < 3; ++e) {
      const int32_t u = triangles[f][e], v = triangles[f][(e + 1) % 3];
      const uint64_t key = (uint64_t(uint32_t(std::min(u, v))) << 32) | uint32_t(std::max(u, v));
      auto [it, fresh] = first_face.try_emplace(key, int32_t(f));
      if (fresh) continue;
      const int32_t g = it->second;
      const Vec3 &n1 = face_normal[g], &n2 = face_normal[f];
      const Vec3& opposite = vertices[triangles[f][(e + 2) % 3]];
      const bool convex = n1.dot(opposite - vertices[u]) < 0.0;
      if (convex && n1.dot(n2) < cos_edge) out.edges.push_back({vertices[u], vertices[v], n1, n2});
    }
  // Corners.
  const double cos_corner = std::cos(0.5 * angle);
  for (size_t i = 0; i < vertices.size(); ++i) {
    if (vertex_faces[i].empty() || !(vertex_normal[i].squaredNorm() > 0.0)) continue;
    const Vec3 n = vertex_normal[i].normalized();
    bool convex = true, sharp = false;
    for (int32_t f : vertex_faces[i]) {
      sharp = sharp || n.dot(face_normal[f]) < cos_corner;
      for (int32_t j : triangles[f]) convex = convex && n.dot(vertices[j] - vertices[i]) <= 0.0;
    }
    if (!convex || !sharp) continue;
    SharpFeatures::Corner c{vertices[i], n, int32_t(out.face_normals.size()),
                            int32_t(vertex_faces[i].size())};
    for (int32_t f : vertex_faces[i]) out.face_normals.push_back(face_normal[f]);
    out.corners.push_back(c);
  }
  return out;
}

SharpFeatures box_features(const Vec3& center, const Vec3& half_extents, const Mat3& axes) {
  // The box as a closed mesh of twelve triangles facing out: its face diagonals are flat, so
  // what remains is its edges and corners.
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k) {
    const Vec3 s((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0);
    corners.push_back(center + axes * s.cwiseProduct(half_extents));
  }
  // Each face by its four corners, counter-clockwise seen from outside (bit 1: x, 2: y, 4: z).
  constexpr std::array<std::array<int32_t, 4>, 6> kFaces = {
      {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}};
  std::vector<Triangle> triangles;
  for (const auto& f : kFaces) {
    triangles.push_back({f[0], f[1], f[2]});
    triangles.push_back({f[0], f[2], f[3]});
  }
  return sharp_features(TriangleShape(std::move(corners), triangles), kSharpAngle);
}

}  // namespace drape
