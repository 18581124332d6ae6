// The cloth's triangles against a moving round body. Particle contacts keep every particle
// outside a collider, but a small body pushed fast into cloth parts the particles in front of
// it: they slide round its sides, and the triangles between them stretch across it until the
// body lies beyond the cloth (a ball at 10 m/s through a hanging curtain). Keeping the
// triangles out too, each pushed out at its point nearest the body, the body pushes the cloth
// ahead of it instead. Spheres and capsules that move: their size is comparable to a cloth's
// cells and they move fast. A still body's cloth rests on it with cells a fraction of its size,
// which dip into it less than the thickness; a box's and a mesh's edges and corners are
// feature_contacts.h's. Each push is a point push (point_push.h), so friction holds the cloth
// there as it does at the particles.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "collision/closest_points.h"
#include "collision/point_push.h"
#include "drape/collider.h"

namespace drape {

/// Whether the solvers keep the cloth's triangles out of this collider, not only particles.
inline bool holds_triangles_out(const Collider& c) {
  return c.moving && (c.type == ColliderType::sphere || c.type == ColliderType::capsule);
}

/// Whether any of the colliders does.
inline bool any_holds_triangles_out(const std::vector<Collider>& colliders) {
  return std::any_of(colliders.begin(), colliders.end(), holds_triangles_out);
}

/// The push for triangle x0 x1 x2 against collider c (sphere or capsule): its point nearest the
/// body (inside the face or on an edge) out to the surface, along the normal there. Fills out's
/// count, weights, normal and depth (the caller names the corners), or returns false where the
/// triangle lies outside the body or its nearest point is a corner (the particle contacts hold
/// those).
inline bool triangle_push(const Collider& c, const Vec3& x0, const Vec3& x1, const Vec3& x2,
                          PointPush& out) {
  // A quick rejection: the triangle's centroid farther from the body's bounding sphere than
  // the triangle's own reach and the thickness.
  const Vec3 g = (x0 + x1 + x2) / 3.0;
  const double span2 =
      std::max({(x0 - g).squaredNorm(), (x1 - g).squaredNorm(), (x2 - g).squaredNorm()});
  const double reach = c.bound_radius + c.thickness;
  const Vec3 to_body = g - c.bound_center;
  if (to_body.squaredNorm() > reach * reach + span2 + 2.0 * reach * std::sqrt(span2)) return false;
  // The body's axis point (a sphere's centre) and the triangle's point nearest each other: for
  // a capsule by alternating the two closest-point queries from the centroid (convex sets:
  // each round comes nearer).
  Vec3 axis_point = c.center;
  TrianglePoint tp = closest_on_triangle(axis_point, x0, x1, x2);
  if (c.type == ColliderType::capsule) {
    const Vec3 ab = c.b - c.a;
    const double ab2 = ab.squaredNorm();
    Vec3 probe = g;
    for (int round = 0; round < 3; ++round) {
      const double s = ab2 > 0.0 ? std::clamp((probe - c.a).dot(ab) / ab2, 0.0, 1.0) : 0.0;
      axis_point = c.a + s * ab;
      tp = closest_on_triangle(axis_point, x0, x1, x2);
      probe = tp.wa * x0 + tp.wb * x1 + tp.wc * x2;
    }
  }
  if (tp.feature >= 4) return false;
  const Vec3 d = tp.wa * x0 + tp.wb * x1 + tp.wc * x2 - axis_point;
  const double distance = d.norm();
  // Out to the body's own surface, not to the thickness the particles keep: cloth resting on a
  // body sags between its particles by less than that, and pushed out there it would lift off
  // the friction that holds it.
  const double depth = c.radius - distance;
  if (!(depth > 0.0) || !(distance > 0.0)) return false;
  out.count = 3;
  out.w[0] = tp.wa, out.w[1] = tp.wb, out.w[2] = tp.wc;
  out.n = d / distance;
  out.depth = depth;
  return true;
}

}  // namespace drape
