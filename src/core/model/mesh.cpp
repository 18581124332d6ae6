// A cloth from any triangle mesh: the checks it must pass, and its springs and masses.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>

#include "drape/error.h"
#include "model/model.h"

namespace drape {

Mat3 MeshTransform::rotation() const {
  constexpr double kRad = std::numbers::pi / 180.0;
  // About x, then y, then z: the last applied stands leftmost.
  return (Eigen::AngleAxisd(rotate.z() * kRad, Vec3::UnitZ()) *
          Eigen::AngleAxisd(rotate.y() * kRad, Vec3::UnitY()) *
          Eigen::AngleAxisd(rotate.x() * kRad, Vec3::UnitX()))
      .toRotationMatrix();
}

std::vector<std::array<int32_t, 2>> triangle_edges(const std::vector<Triangle>& triangles) {
  std::vector<std::array<int32_t, 2>> edges;
  edges.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int32_t i = t[k], j = t[(k + 1) % 3];
      edges.push_back({std::min(i, j), std::max(i, j)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

Vec3 MeshTransform::apply(const Vec3& p) const {
  return rotation() * p.cwiseProduct(scale) + translate;
}

namespace model {

namespace {

// "triangle 12" or, for a mesh read from a file, "the face on line 40".
std::string triangle_name(const ClothMesh& mesh, size_t t) {
  if (t < mesh.triangle_line.size())
    return "the face on line " + std::to_string(mesh.triangle_line[t]);
  return "triangle " + std::to_string(t);
}

// The mesh's edges as (smaller, larger) vertex pairs, sorted, each with the triangles that
// hold it: edge e is pairs[e], its triangles faces[edge_begin[e] .. edge_begin[e + 1]).
struct Edges {
  std::vector<std::pair<int32_t, int32_t>> pairs;
  std::vector<int32_t> edge_begin, faces;

  explicit Edges(const std::vector<Triangle>& triangles) {
    std::vector<std::pair<std::pair<int32_t, int32_t>, int32_t>> all;
    all.reserve(3 * triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
        all.push_back({{std::min(a, b), std::max(a, b)}, static_cast<int32_t>(t)});
      }
    }
    std::sort(all.begin(), all.end());
    for (size_t k = 0; k < all.size(); ++k) {
      if (k == 0 || all[k].first != all[k - 1].first) {
        pairs.push_back(all[k].first);
        edge_begin.push_back(static_cast<int32_t>(faces.size()));
      }
      faces.push_back(all[k].second);
    }
    edge_begin.push_back(static_cast<int32_t>(faces.size()));
  }
  size_t size() const { return pairs.size(); }
  int32_t count(size_t e) const { return edge_begin[e + 1] - edge_begin[e]; }
};

// The corner of triangle t that is neither a nor b.
int32_t far_corner(const Triangle& t, int32_t a, int32_t b) {
  for (int32_t v : t)
    if (v != a && v != b) return v;
  return t[0];
}

}  // namespace

void check_mesh(const ClothMesh& mesh, const std::string& path) {
  auto fail = [&](const std::string& problem) { throw InputError(path, problem); };
  const size_t n = mesh.positions.size();
  if (mesh.triangles.empty()) fail("has no triangles (a cloth needs faces, not only vertices)");
  if (n > 100'000'000) fail("has " + std::to_string(n) + " vertices, more than 100000000");
  for (size_t v = 0; v < n; ++v)
    if (!mesh.positions[v].allFinite())
      fail("vertex " + std::to_string(v) + " has a coordinate that is not a finite number");
  std::vector<uint8_t> used(n, 0);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int32_t v : mesh.triangles[t]) {
      if (v < 0 || static_cast<size_t>(v) >= n)
        fail(triangle_name(mesh, t) + " names vertex " + std::to_string(v) + ", but there are " +
             std::to_string(n) + " vertices (0 to " + std::to_string(n - 1) + ")");
      used[v] = 1;
    }
  }
  for (size_t v = 0; v < n; ++v)
    if (!used[v])
      fail("vertex " + std::to_string(v) +
           " belongs to no triangle (a particle needs an area for its mass); remove it");
  if (!mesh.triangle_texcoords.empty()) {
    if (mesh.triangle_texcoords.size() != mesh.triangles.size())
      fail("has texture coordinates for some triangles only");
    for (size_t t = 0; t < mesh.triangle_texcoords.size(); ++t)
      for (int32_t k : mesh.triangle_texcoords[t])
        if (k < 0 || static_cast<size_t>(k) >= mesh.texcoords.size())
          fail(triangle_name(mesh, t) + " names texture coordinate " + std::to_string(k) +
               ", but there are " + std::to_string(mesh.texcoords.size()));
  }
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]],
               &c = mesh.positions[tri[2]];
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // Zero area up to round-off: the cross product of two sides against the longest side.
    if (!((b - a).cross(c - a).norm() > 1e-12 * longest))
      fail(triangle_name(mesh, t) + " (vertices " + std::to_string(tri[0]) + ", " +
           std::to_string(tri[1]) + ", " + std::to_string(tri[2]) +
           ") has zero area; a cloth's triangles must not be degenerate");
  }
  const Edges edges(mesh.triangles);
  for (size_t e = 0; e < edges.size(); ++e) {
    if (edges.count(e) <= 2) continue;
    std::string faces;
    for (int32_t k = edges.edge_begin[e]; k < edges.edge_begin[e + 1]; ++k)
      faces += (faces.empty() ? "" : ", ") + triangle_name(mesh, edges.faces[k]);
    fail("the edge between vertices " + std::to_string(edges.pairs[e].first) + " and " +
         std::to_string(edges.pairs[e].second) + " is shared by " +
         std::to_string(edges.count(e)) + " triangles (" + faces +
         "); a cloth must be a manifold surface, where an edge has one or two triangles");
  }
}

ClothModel from_mesh(const ClothDef& def) {
  const ClothMesh& mesh = *def.mesh;
  ClothModel m;
  const int32_t n = static_cast<int32_t>(mesh.positions.size());
  m.rest_position.resize(n);
  for (int32_t v = 0; v < n; ++v) m.rest_position[v] = def.transform.apply(mesh.positions[v]);
  m.triangles = mesh.triangles;
  const std::vector<Vec3>& x = m.rest_position;

  // Masses by area: each vertex carries a third of each triangle around it.
  std::vector<double> area(n, 0.0);
  double total = 0.0;
  for (const Triangle& t : m.triangles) {
    const double a = 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
    total += a;
    for (int32_t v : t) area[v] += a / 3.0;
  }
  m.mass.resize(n);
  for (int32_t v = 0; v < n; ++v) m.mass[v] = def.mass * area[v] / total;

  // A structural spring on every edge; a bending spring across every edge two triangles share,
  // between their far corners.
  const Edges edges(m.triangles);
  for (const auto& [i, j] : edges.pairs)
    m.springs.push_back({i, j, (x[j] - x[i]).norm(), def.structural.stiffness,
                         def.structural.damping, SpringKind::structural});
  for (size_t e = 0; e < edges.size(); ++e) {
    if (edges.count(e) != 2) continue;
    const auto [i, j] = edges.pairs[e];
    const int32_t a = far_corner(m.triangles[edges.faces[edges.edge_begin[e]]], i, j);
    const int32_t b = far_corner(m.triangles[edges.faces[edges.edge_begin[e] + 1]], i, j);
    const double rest = (x[b] - x[a]).norm();
    if (a == b || rest == 0.0) continue;
    m.springs.push_back({std::min(a, b), std::max(a, b), rest, def.bending.stiffness,
                         def.bending.damping, SpringKind::bending});
  }

  // Texture coordinates: per vertex its first corner's, and per corner as given where a vertex
  // has several (a seam). Without any, the rest shape projected on the plane of its two widest
  // extents, scaled alike so that the checker's squares stay square.
  m.uv.assign(n, Vec2::Zero());
  if (!mesh.triangle_texcoords.empty()) {
    m.has_texcoords = true;
    // The model's v runs down the texture (as the grid's rows), the file's up (OBJ).
    std::vector<Vec2> texcoords(mesh.texcoords.size());
    for (size_t k = 0; k < texcoords.size(); ++k)
      texcoords[k] = Vec2(mesh.texcoords[k].x(), 1.0 - mesh.texcoords[k].y());
    std::vector<int32_t> first(n, -1);
    bool seams = false;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const int32_t v = m.triangles[t][k], c = mesh.triangle_texcoords[t][k];
        if (first[v] < 0) {
          first[v] = c;
          m.uv[v] = texcoords[c];
        } else {
          seams = seams || texcoords[c] != m.uv[v];
        }
      }
    }
    if (seams) {
      m.texcoords = texcoords;
      m.triangle_texcoords = mesh.triangle_texcoords;
    }
  } else {
    Vec3 lo = x[0], hi = x[0];
    for (const Vec3& p : x) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Vec3 extent = hi - lo;
    int a = 0, b = 1;  // the two widest axes, in order
    if (extent[2] > extent[a] || extent[2] > extent[b]) (extent[a] < extent[b] ? a : b) = 2;
    if (a > b) std::swap(a, b);
    const double scale = std::max(extent[a], extent[b]);
    for (int32_t v = 0; v < n; ++v)
      m.uv[v] = scale > 0.0 ? Vec2((x[v][a] - lo[a]) / scale, (x[v][b] - lo[b]) / scale)
                            : Vec2::Zero();
  }
  finish(m);
  return m;
}

}  // namespace model
}  // namespace drape
