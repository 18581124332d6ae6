// Closest points between a point and a triangle, and between two segments: the distance
// queries of cloth–cloth contact (Ericson, "Real-Time Collision Detection", 2005, 5.1.5 and
// 5.1.9).
#pragma once

#include <algorithm>

#include "drape/math.h"

namespace drape {

/// The point of triangle abc nearest p, as barycentric weights (wa, wb, wc) summing to 1.
/// `interior` says it lies inside the face (all weights positive), not on an edge or a corner;
/// `feature` which of them it lies on: 0 the face, 1..3 the edges ab, bc, ca, 4..6 the corners
/// a, b, c (a mesh's pseudo-normals are per feature).
struct TrianglePoint {
  double wa = 1.0, wb = 0.0, wc = 0.0;
  bool interior = false;
  int feature = 4;
};

inline TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                         const Vec3& c) {
  // Ericson's walk over the Voronoi regions of the corners, the edges and the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0, false, 4};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0, false, 5};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {1.0 - t, t, 0.0, false, 1};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0, false, 6};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {1.0 - t, 0.0, t, false, 3};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - t, t, false, 2};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return {1.0, 0.0, 0.0, false, 4};  // a degenerate (zero-area) triangle
  const double v = vb / sum, w = vc / sum;
  return {1.0 - v - w, v, w, true, 0};
}

/// Whether p lies over the face of triangle abc (its projection on the plane inside the
/// triangle, or outside it by at most `margin` in barycentric terms), with the projection's
/// barycentric weights clamped into the triangle. A point over a corner or an edge shared by
/// several triangles is over each of them within the margin, so none lets it slip between.
inline TrianglePoint over_face(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                               double margin) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d00 = ab.dot(ab), d01 = ab.dot(ac), d11 = ac.dot(ac);
  const double d20 = ap.dot(ab), d21 = ap.dot(ac);
  const double denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0.0)) return {1.0, 0.0, 0.0, false, 4};  // degenerate
  double wb = (d11 * d20 - d01 * d21) / denominator, wc = (d00 * d21 - d01 * d20) / denominator;
  double wa = 1.0 - wb - wc;
  if (std::min({wa, wb, wc}) < -margin) return {wa, wb, wc, false, 4};
  wa = std::max(wa, 0.0), wb = std::max(wb, 0.0), wc = std::max(wc, 0.0);
  const double sum = wa + wb + wc;
  return {wa / sum, wb / sum, wc / sum, true, 0};
}

/// The parameters s, t in [0, 1] of the nearest points p0 + s(p1 − p0) and q0 + t(q1 − q0) of
/// two segments; `interior` says both lie strictly inside their segments.
struct SegmentPoints {
  double s = 0.0, t = 0.0;
  bool interior = false;
};

inline SegmentPoints closest_between_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                              const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kTiny = 1e-30;
  double s = 0.0, t = 0.0;
  if (a <= kTiny && e <= kTiny) return {0.0, 0.0, false};
  if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denominator = a * e - b * b;
      // Parallel segments (denominator 0): any s will do; take 0 and let t follow.
      s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {s, t, s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0};
}

}  // namespace drape
