#include "collision/triangle_shape.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "collision/closest_points.h"
#include "collision/crossings.h"
#include "drape/cloth.h"

namespace drape {

namespace {

constexpr int kLeafSize = 4;

// The closest point to p on triangle abc and its feature (closest_points.h).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int& feature) {
  const TrianglePoint q = drape::closest_on_triangle(p, a, b, c);
  feature = q.feature;
  return q.wa * a + q.wb * b + q.wc * c;
}

double box_distance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 d = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

}  // namespace

TriangleShape::TriangleShape(std::vector<Vec3> vertices, const std::vector<Triangle>& triangles)
    : vertices_(std::move(vertices)) {
  // Keep the triangles with an area.
  for (const Triangle& t : triangles) {
    const Vec3 n = (vertices_[t[1]] - vertices_[t[0]]).cross(vertices_[t[2]] - vertices_[t[0]]);
    if (n.squaredNorm() > 0.0) triangles_.push_back(t);
  }
  // Closed: every edge is met twice, once each way.
  std::unordered_map<uint64_t, std::array<int32_t, 2>> edges;  // edge → its (up to 2) faces
  for (size_t f = 0; f < triangles_.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      auto [it, fresh] = edges.try_emplace(edge_key(triangles_[f][e], triangles_[f][(e + 1) % 3]),
                                           std::array<int32_t, 2>{int32_t(f), -1});
      if (fresh) continue;
      if (it->second[1] == -1)
        it->second[1] = int32_t(f);
      else
        it->second[1] = -2;  // met three times or more: not a closed surface
    }
  closed_ = !triangles_.empty();
  for (const auto& [k, faces] : edges) closed_ = closed_ && faces[1] >= 0;
  // A closed mesh faces out: its signed volume is positive. Turn it if it faces in.
  if (closed_) {
    double volume = 0.0;
    for (const Triangle& t : triangles_)
      volume += vertices_[t[0]].dot(vertices_[t[1]].cross(vertices_[t[2]]));
    if (volume < 0.0)
      for (Triangle& t : triangles_) std::swap(t[1], t[2]);
  }
  // Normals: per face; per vertex weighted by the face's angle there; per edge the sum of its
  // faces' (Bærentzen & Aanæs: any positive weights for the edge, angles for the vertex).
  const size_t nt = triangles_.size();
  face_normal_.resize(nt);
  vertex_normal_.assign(vertices_.size(), Vec3::Zero());
  for (size_t f = 0; f < nt; ++f) {
    const Triangle& t = triangles_[f];
    face_normal_[f] =
        (vertices_[t[1]] - vertices_[t[0]]).cross(vertices_[t[2]] - vertices_[t[0]]).normalized();
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = (vertices_[t[(k + 1) % 3]] - vertices_[t[k]]).normalized();
      const Vec3 w = (vertices_[t[(k + 2) % 3]] - vertices_[t[k]]).normalized();
      vertex_normal_[t[k]] += std::acos(std::clamp(u.dot(w), -1.0, 1.0)) * face_normal_[f];
    }
  }
  edge_normal_.resize(3 * nt);
  for (size_t f = 0; f < nt; ++f)
    for (int e = 0; e < 3; ++e) {
      const auto& faces = edges.at(edge_key(triangles_[f][e], triangles_[f][(e + 1) % 3]));
      Vec3 n = face_normal_[faces[0]];
      if (faces[1] >= 0) n += face_normal_[faces[1]];
      edge_normal_[3 * f + e] = n;
    }
  // The hierarchy: median splits along the longest axis of the centroids' box.
  lo_ = hi_ = vertices_.empty() ? Vec3::Zero() : vertices_[0];
  for (const Vec3& v : vertices_) {
    lo_ = lo_.cwiseMin(v);
    hi_ = hi_.cwiseMax(v);
  }
  std::vector<Vec3> centroids(nt);
  order_.resize(nt);
  for (size_t f = 0; f < nt; ++f) {
    const Triangle& t = triangles_[f];
    centroids[f] = (vertices_[t[0]] + vertices_[t[1]] + vertices_[t[2]]) / 3.0;
    order_[f] = int32_t(f);
  }
  nodes_.reserve(2 * nt / kLeafSize + 1);
  if (nt > 0) build(0, int32_t(nt), centroids);
}

int32_t TriangleShape::build(int32_t begin, int32_t end, std::vector<Vec3>& centroids) {
  const int32_t index = int32_t(nodes_.size());
  nodes_.push_back({});
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Vec3 clo = lo, chi = hi;
  for (int32_t k = begin; k < end; ++k) {
    const Triangle& t = triangles_[order_[k]];
    for (int v = 0; v < 3; ++v) {
      lo = lo.cwiseMin(vertices_[t[v]]);
      hi = hi.cwiseMax(vertices_[t[v]]);
    }
    clo = clo.cwiseMin(centroids[order_[k]]);
    chi = chi.cwiseMax(centroids[order_[k]]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int32_t a, int32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  build(begin, mid, centroids);
  const int32_t right = build(mid, end, centroids);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

void TriangleShape::closest(const Vec3& p, double& best2, int32_t& tri, Vec3& point,
                            int& feature) const {
  int32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_distance2(p, node.lo, node.hi) >= best2) continue;
    if (node.count > 0) {
      for (int32_t k = node.first; k < node.first + node.count; ++k) {
        const Triangle& t = triangles_[order_[k]];
        int f = 0;
        const Vec3 q = closest_on_triangle(p, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]], f);
        const double d2 = (p - q).squaredNorm();
        if (d2 < best2) best2 = d2, tri = order_[k], point = q, feature = f;
      }
      continue;
    }
    // Nearer child last, so it is searched first.
    const int32_t left = int32_t(&node - nodes_.data()) + 1, right = node.first;
    const double dl = box_distance2(p, nodes_[left].lo, nodes_[left].hi),
                 dr = box_distance2(p, nodes_[right].lo, nodes_[right].hi);
    if (top + 2 > 64) continue;  // deeper than any balanced tree of 2^60 leaves
    if (dl < dr) {
      stack[top++] = right;
      stack[top++] = left;
    } else {
      stack[top++] = left;
      stack[top++] = right;
    }
  }
}

template <class F>
void TriangleShape::each_crossing(const Vec3& a, const Vec3& b, F&& f) const {
  const Vec3 lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  int32_t stack[64];
  int top = 0;
  if (!nodes_.empty()) stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if ((node.hi.array() < lo.array()).any() || (hi.array() < node.lo.array()).any()) continue;
    if (node.count > 0) {
      for (int32_t k = node.first; k < node.first + node.count; ++k) {
        const int32_t tri = order_[k];
        const Triangle& t = triangles_[tri];
        const Vec3 &u = vertices_[t[0]], &v = vertices_[t[1]], &w = vertices_[t[2]];
        if (!segment_crosses_triangle(a, b, u, v, w)) continue;
        // Where a–b meets the triangle's plane (a crossing one is not parallel to it).
        const Vec3& n = face_normal_[tri];
        if (f(tri, n.dot(u - a) / n.dot(b - a))) return;
      }
      continue;
    }
    if (top + 2 > 64) continue;  // deeper than any balanced tree of 2^60 leaves
    stack[top++] = int32_t(&node - nodes_.data()) + 1;
    stack[top++] = node.first;
  }
}

bool TriangleShape::crossed_by(const Vec3& a, const Vec3& b) const {
  bool crossed = false;
  each_crossing(a, b, [&](int32_t, double) { return crossed = true; });
  return crossed;
}

int32_t TriangleShape::first_crossing(const Vec3& a, const Vec3& b) const {
  int32_t first = -1;
  double nearest = 0.0;
  each_crossing(a, b, [&](int32_t tri, double along) {
    if (first < 0 || along < nearest) first = tri, nearest = along;
    return false;
  });
  return first;
}

Vec3 TriangleShape::pseudo_normal(int32_t tri, int feature) const {
  if (feature == 0) return face_normal_[tri];
  if (feature <= 3) return edge_normal_[3 * tri + feature - 1];
  return vertex_normal_[triangles_[tri][feature - 4]];
}

double TriangleShape::signed_distance(const Vec3& p, Vec3& normal) const {
  double best2 = std::numeric_limits<double>::infinity();
  int32_t tri = -1;
  Vec3 point = Vec3::Zero();
  int feature = 0;
  if (!nodes_.empty()) closest(p, best2, tri, point, feature);
  if (tri < 0) {
    normal = Vec3::UnitY();
    return std::numeric_limits<double>::infinity();
  }
  const double dist = std::sqrt(best2);
  const Vec3 pseudo = pseudo_normal(tri, feature);
  const Vec3 away = p - point;
  if (!closed_) {  // two-sided: the side p is on
    normal = dist > 0.0 ? Vec3(away / dist) : face_normal_[tri];
    return dist;
  }
  const bool inside = away.dot(pseudo) < 0.0;
  normal = dist > 0.0 ? Vec3((inside ? -away : away) / dist) : pseudo.normalized();
  return inside ? -dist : dist;
}

int64_t TriangleShape::bytes() const {
  return heap_bytes(vertices_, triangles_, face_normal_, vertex_normal_, edge_normal_, nodes_,
                    order_);
}

}  // namespace drape
