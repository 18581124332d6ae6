// An intersection count for the tests, independent of the library's: every pair of triangles,
// each edge against the other triangle by its plane crossing and barycentric signs with a
// tolerance for touching (not the certified orientation predicates count_self_intersections
// uses).
#pragma once

#include <cstdint>
#include <vector>

#include "drape/math.h"
#include "drape/mesh.h"

namespace drape::testing_support {

// Segment pq passes through the inside of triangle abc: p and q on either side of its plane,
// and the point where pq meets the plane inside all three edges, each by more than a relative
// 1e-12: a touch (a corner or an edge lying on the other triangle, to within rounding) is not
// a crossing, as for the library.
inline bool crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr double kTouch = 1e-12;
  const Vec3 n = (b - a).cross(c - a);
  const double scale = n.norm() * ((p - a).norm() + (q - a).norm() + (b - a).norm());
  const double dp = n.dot(p - a), dq = n.dot(q - a), plane = kTouch * scale;
  if (!((dp < -plane && dq > plane) || (dp > plane && dq < -plane))) return false;
  const Vec3 hit = p + dp / (dp - dq) * (q - p);
  const double inside = kTouch * n.squaredNorm();
  return n.dot((b - a).cross(hit - a)) > inside && n.dot((c - b).cross(hit - b)) > inside &&
         n.dot((a - c).cross(hit - c)) > inside;
}

/// Whether triangles S and T share a vertex.
inline bool share_a_vertex(const Triangle& S, const Triangle& T) {
  for (int32_t i : S)
    for (int32_t j : T)
      if (i == j) return true;
  return false;
}

/// Whether triangles S and T at x cross: an edge of either through the other.
inline bool triangles_cross(const Triangle& S, const Triangle& T, const std::vector<Vec3>& x) {
  for (int e = 0; e < 3; ++e)
    if (crosses(x[S[e]], x[S[(e + 1) % 3]], x[T[0]], x[T[1]], x[T[2]]) ||
        crosses(x[T[e]], x[T[(e + 1) % 3]], x[S[0]], x[S[1]], x[S[2]]))
      return true;
  return false;
}

/// Crossing pairs of triangles that share no vertex, every pair tested.
inline int64_t brute_force_crossings(const std::vector<Triangle>& triangles,
                                     const std::vector<Vec3>& x) {
  int64_t count = 0;
  for (size_t s = 0; s < triangles.size(); ++s)
    for (size_t t = s + 1; t < triangles.size(); ++t)
      count += !share_a_vertex(triangles[s], triangles[t]) &&
               triangles_cross(triangles[s], triangles[t], x);
  return count;
}

}  // namespace drape::testing_support
