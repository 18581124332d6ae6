#include "collision/sharp_features.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <utility>

namespace drape {

namespace {

// The unit direction across edge a–b, in the plane of the edge and `opposite`, away from
// `opposite`: where a face's rim points.
Vec3 away_across(const Vec3& a, const Vec3& b, const Vec3& opposite) {
  const Vec3 ab = (b - a).normalized();
  const Vec3 in = opposite - a;
  return -(in - in.dot(ab) * ab).normalized();
}

// The angle of triangle t at its vertex i.
double angle_at(const std::vector<Vec3>& vertices, const Triangle& t, int32_t i) {
  const int k = t[0] == i ? 0 : t[1] == i ? 1 : 2;
  const Vec3 e1 = vertices[t[(k + 1) % 3]] - vertices[i];
  const Vec3 e2 = vertices[t[(k + 2) % 3]] - vertices[i];
  return std::atan2(e1.cross(e2).norm(), e1.dot(e2));
}

// A face's normal turned to the side `toward` points to.
Vec3 facing(const Vec3& normal, const Vec3& toward) {
  return normal.dot(toward) < 0.0 ? Vec3(-normal) : normal;
}

// Each edge with the faces that meet it, in the order first met; an open mesh's rim edges
// have one.
struct Met {
  int32_t u, v, face, opposite;
  int32_t other_face = -1, other_opposite = -1;
  bool agree = true;  ///< whether the two faces are wound alike (they pass it opposite ways)
};
struct EdgeTable {
  std::vector<Met> met;
  std::vector<int32_t> shared;  ///< the edges two faces meet, in the order the second meets them
};

EdgeTable edge_table(const std::vector<Triangle>& triangles) {
  EdgeTable table;
  std::unordered_map<uint64_t, int32_t> slot;
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const int32_t u = triangles[f][e], v = triangles[f][(e + 1) % 3];
      const int32_t opposite = triangles[f][(e + 2) % 3];
      auto [it, fresh] = slot.try_emplace(edge_key(u, v), int32_t(table.met.size()));
      if (fresh) {
        table.met.push_back({u, v, int32_t(f), opposite});
      } else {
        Met& m = table.met[it->second];
        m.other_face = int32_t(f);
        m.other_opposite = opposite;
        m.agree = m.u != u;
        table.shared.push_back(it->second);
      }
    }
  return table;
}

// The faces' normals turned to one side across each connected piece of a two-sided mesh (its
// triangles may be wound either way).
std::vector<Vec3> one_sided_normals(const std::vector<Vec3>& face_normal, const EdgeTable& table) {
  const size_t nt = face_normal.size();
  std::vector<std::vector<std::pair<int32_t, bool>>> next(nt);
  for (const Met& m : table.met)
    if (m.other_face >= 0) {
      next[m.face].emplace_back(m.other_face, m.agree);
      next[m.other_face].emplace_back(m.face, m.agree);
    }
  std::vector<int8_t> turned(nt, -1);
  std::vector<int32_t> stack;
  for (size_t seed = 0; seed < nt; ++seed) {
    if (turned[seed] >= 0) continue;
    turned[seed] = 0;
    stack.assign(1, int32_t(seed));
    while (!stack.empty()) {
      const int32_t f = stack.back();
      stack.pop_back();
      for (const auto& [g, agree] : next[f])
        if (turned[g] < 0) {
          turned[g] = int8_t(agree ? turned[f] : 1 - turned[f]);
          stack.push_back(g);
        }
    }
  }
  std::vector<Vec3> normal = face_normal;
  for (size_t f = 0; f < nt; ++f)
    if (turned[f] == 1) normal[f] = -normal[f];
  return normal;
}

// Ridges: edges two faces meet at a convex angle sharper than `angle`.
void add_ridges(const TriangleShape& shape, const EdgeTable& table, double angle,
                SharpFeatures& out) {
  const std::vector<Vec3>& vertices = shape.vertices();
  const std::vector<Vec3>& face_normal = shape.face_normals();
  const double cos_edge = std::cos(angle);
  for (const int32_t k : table.shared) {
    const Met& m = table.met[k];
    // As the second face passes it.
    const Vec3 &a = vertices[m.agree ? m.v : m.u], &b = vertices[m.agree ? m.u : m.v];
    // Outward normals are those each face's neighbour lies below: on a closed mesh its own
    // (and the edge is concave where they are not), on a two-sided one whichever they are.
    Vec3 n1 = face_normal[m.face], n2 = face_normal[m.other_face];
    const Vec3 to2 = vertices[m.other_opposite] - a, to1 = vertices[m.opposite] - a;
    if (!shape.closed()) {
      n1 = facing(n1, -to2);
      n2 = facing(n2, -to1);
    }
    // (A flat edge's neighbours lie in the plane, either side of it by rounding.)
    const bool convex = n1.dot(to2) < -1e-9 * to2.norm() && n2.dot(to1) < -1e-9 * to1.norm();
    if (!convex || !(n1.dot(n2) < cos_edge)) continue;
    const Vec3 sum = n1 + n2;
    // Folded nearly flat onto itself, the edge is a blade again.
    const Vec3 dir = sum.norm() > 1e-6 ? Vec3(sum.normalized()) : away_across(a, b, to1 + a);
    out.edges.push_back({a, b, n1, n2, dir});
  }
}

// Blades (only an open mesh has them): a rim edge's one face's two sides meet there. Each
// knows the next rim edges' out directions at its ends. Returns each vertex's rim neighbours.
std::vector<std::vector<int32_t>> add_blades(const TriangleShape& shape, const EdgeTable& table,
                                             SharpFeatures& out) {
  const std::vector<Vec3>& vertices = shape.vertices();
  std::vector<std::vector<int32_t>> rim_neighbours(vertices.size());
  std::unordered_map<uint64_t, int32_t> blade_of;
  std::vector<std::array<int32_t, 2>> ends;  // per blade, its two vertices
  const size_t first_blade = out.edges.size();
  for (const Met& m : table.met) {
    if (m.other_face >= 0) continue;
    const Vec3 &a = vertices[m.u], &b = vertices[m.v];
    const Vec3& n = shape.face_normals()[m.face];
    blade_of[edge_key(m.u, m.v)] = int32_t(out.edges.size());
    out.edges.push_back({a, b, n, -n, away_across(a, b, vertices[m.opposite]), true});
    rim_neighbours[m.u].push_back(m.v);
    rim_neighbours[m.v].push_back(m.u);
    ends.push_back({m.u, m.v});
  }
  for (size_t k = 0; k < ends.size(); ++k)
    for (int end = 0; end < 2; ++end) {
      const int32_t v = ends[k][end], other = ends[k][1 - end];
      if (rim_neighbours[v].size() != 2) continue;
      const int32_t next =
          rim_neighbours[v][0] == other ? rim_neighbours[v][1] : rim_neighbours[v][0];
      out.edges[first_blade + k].next_out[end] = out.edges[blade_of.at(edge_key(v, next))].out;
    }
  return rim_neighbours;
}

// A rim vertex is a corner where its faces span less than a half turn less the angle, and only
// where the rim passes through once (two rim neighbours).
void add_rim_corner(const TriangleShape& shape, const std::vector<int32_t>& faces, int32_t i,
                    const std::vector<int32_t>& rim_neighbours, double angle, SharpFeatures& out) {
  const std::vector<Vec3>& vertices = shape.vertices();
  if (rim_neighbours.size() != 2) return;
  double span = 0.0;
  for (int32_t f : faces) span += angle_at(vertices, shape.triangles()[f], i);
  if (!(span < std::numbers::pi - angle)) return;
  const Vec3& corner = vertices[i];
  const Vec3 u1 = (vertices[rim_neighbours[0]] - corner).normalized();
  const Vec3 u2 = (vertices[rim_neighbours[1]] - corner).normalized();
  if (!((u1 + u2).squaredNorm() > 0.0)) return;
  const int32_t first = int32_t(out.face_normals.size());
  out.corners.push_back({corner, -(u1 + u2).normalized(), first, 0, true, {u1, u2}});
}

// A vertex inside the surface is a corner where it is convex on its normal's side (either, on a
// two-sided mesh), and sharp where a face turns from that normal by more than half the angle.
void add_inner_corner(const TriangleShape& shape, const std::vector<Vec3>& normal,
                      const std::vector<int32_t>& faces, int32_t i, double angle,
                      SharpFeatures& out) {
  const std::vector<Vec3>& vertices = shape.vertices();
  const std::vector<Triangle>& triangles = shape.triangles();
  const bool two_sided = !shape.closed();
  Vec3 vertex_n = shape.vertex_normals()[i];
  if (two_sided) {
    vertex_n.setZero();
    for (int32_t f : faces) vertex_n += angle_at(vertices, triangles[f], i) * normal[f];
  }
  if (!(vertex_n.squaredNorm() > 0.0)) return;
  const double cos_corner = std::cos(0.5 * angle);
  for (const double side : {1.0, -1.0}) {
    if (side < 0.0 && !two_sided) break;
    const Vec3 n = side * vertex_n.normalized();
    bool convex = true, sharp = false;
    for (int32_t f : faces) {
      sharp = sharp || n.dot(side * normal[f]) < cos_corner;
      for (int32_t j : triangles[f]) {  // (a neighbour on the plane stays on it rounded)
        const Vec3 d = vertices[j] - vertices[i];
        convex = convex && n.dot(d) <= 1e-12 * d.norm();
      }
    }
    if (!convex || !sharp) continue;
    const int32_t first = int32_t(out.face_normals.size());
    for (int32_t f : faces) out.face_normals.push_back(side * normal[f]);
    out.corners.push_back({vertices[i], n, first, int32_t(faces.size())});
    return;
  }
}

}  // namespace

SharpFeatures sharp_features(const TriangleShape& shape, double angle) {
  SharpFeatures out;
  const bool two_sided = !shape.closed();
  const std::vector<Triangle>& triangles = shape.triangles();
  const EdgeTable table = edge_table(triangles);
  // A closed mesh's faces face out already.
  const std::vector<Vec3> normal =
      two_sided ? one_sided_normals(shape.face_normals(), table) : shape.face_normals();

  add_ridges(shape, table, angle, out);
  std::vector<std::vector<int32_t>> rim_neighbours;
  if (two_sided) rim_neighbours = add_blades(shape, table, out);

  std::vector<std::vector<int32_t>> vertex_faces(shape.vertices().size());
  for (size_t f = 0; f < triangles.size(); ++f)
    for (int32_t v : triangles[f]) vertex_faces[v].push_back(int32_t(f));
  for (size_t i = 0; i < vertex_faces.size(); ++i) {
    if (vertex_faces[i].empty()) continue;
    if (two_sided && !rim_neighbours[i].empty())
      add_rim_corner(shape, vertex_faces[i], int32_t(i), rim_neighbours[i], angle, out);
    else
      add_inner_corner(shape, normal, vertex_faces[i], int32_t(i), angle, out);
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
