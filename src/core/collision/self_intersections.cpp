#include "drape/self_intersections.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "crossings.h"
#include "parallel.h"

namespace drape {

namespace {

// Shewchuk's bound on the rounding error of orient3d evaluated in doubles, relative to its
// permanent (errboundA in "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates", 1997): a determinant larger than this is certainly of its sign.
constexpr double kRoundoff = 0x1p-53;
constexpr double kOrientationBound = (7.0 + 56.0 * kRoundoff) * kRoundoff;
// Below this permanent the products may have lost bits to underflow and the bound no longer
// holds; coordinates in metres never get there.
constexpr double kSmallestPermanent = 1e-280;

// The sign of det[a − d, b − d, c − d]: which side of the plane through a, b, c the point d
// lies on. 0 when d is on the plane or too close to it for doubles to tell (not an exact
// predicate, but a certified one: a sign it gives is never wrong).
int orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x() - d.x(), bdx = b.x() - d.x(), cdx = c.x() - d.x();
  const double ady = a.y() - d.y(), bdy = b.y() - d.y(), cdy = c.y() - d.y();
  const double adz = a.z() - d.z(), bdz = b.z() - d.z(), cdz = c.z() - d.z();
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double determinant =
      adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  if (!(permanent > kSmallestPermanent)) return 0;
  const double bound = kOrientationBound * permanent;
  return determinant > bound ? 1 : determinant < -bound ? -1 : 0;
}

// Two triangles cross when an edge of either passes through the other: the segment where two
// crossing triangles meet ends on such edges.
bool triangles_cross(const Vec3* s, const Vec3* t) {
  for (int e = 0; e < 3; ++e) {
    if (segment_crosses_triangle(s[e], s[(e + 1) % 3], t[0], t[1], t[2])) return true;
    if (segment_crosses_triangle(t[e], t[(e + 1) % 3], s[0], s[1], s[2])) return true;
  }
  return false;
}

bool share_a_vertex(const Triangle& s, const Triangle& t) {
  for (int32_t i : s)
    for (int32_t j : t)
      if (i == j) return true;
  return false;
}

// Whether all three corners of t lie strictly on one side of s's plane: then the two cannot
// cross (a point of s's edge inside t would be off s's plane). Most neighbouring pairs of a
// smooth cloth end here, before the edge tests.
bool apart(const Vec3* s, const Vec3* t) {
  const int side = orientation(s[0], s[1], s[2], t[0]);
  return side != 0 && orientation(s[0], s[1], s[2], t[1]) == side &&
         orientation(s[0], s[1], s[2], t[2]) == side;
}

}  // namespace

// The three orientations of pq with the triangle's edges agree; any zero means touching.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c) {
  const int side_p = orientation(a, b, c, p), side_q = orientation(a, b, c, q);
  if (side_p == 0 || side_q == 0 || side_p == side_q) return false;
  const int ab = orientation(p, q, a, b);
  if (ab == 0) return false;
  return orientation(p, q, b, c) == ab && orientation(p, q, c, a) == ab;
}

void CrossingFinder::find(const std::vector<Triangle>& triangles,
                          const std::vector<Vec3>& positions, std::vector<TrianglePair>& out) {
  out.clear();
  // Boxes of the triangles whose corners are all finite.
  kept_.clear();
  boxes_.resize(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Vec3 &a = positions[triangles[t][0]], &b = positions[triangles[t][1]],
               &c = positions[triangles[t][2]];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    boxes_[t] = {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
    kept_.push_back(static_cast<int32_t>(t));
  }
  if (kept_.size() < 2) return;
  grid_.build(boxes_, kept_);

  // Each pair in each cell they share, tested only in the one cell where the grid reports it.
  // Found per cell in parallel, kept in cell order: the same list for any thread count.
  const int64_t cells = grid_.cells();
  found_.clear();
#pragma omp parallel if (worth_threads(grid_.entries()))
  {
    std::vector<TrianglePair>& mine = found_.mine();
#pragma omp for schedule(static) nowait
    for (int64_t cell = 0; cell < cells; ++cell)
      grid_.each_pair_in(cell, [&](int32_t s, int32_t t) {
        if (share_a_vertex(triangles[s], triangles[t])) return;
        const Vec3 corners_s[3] = {positions[triangles[s][0]], positions[triangles[s][1]],
                                   positions[triangles[s][2]]};
        const Vec3 corners_t[3] = {positions[triangles[t][0]], positions[triangles[t][1]],
                                   positions[triangles[t][2]]};
        if (apart(corners_s, corners_t) || apart(corners_t, corners_s)) return;
        if (triangles_cross(corners_s, corners_t)) mine.push_back({s, t});
      });
  }
  found_.gather(out);
  std::sort(out.begin(), out.end(), [](const TrianglePair& a, const TrianglePair& b) {
    return a.s != b.s ? a.s < b.s : a.t < b.t;
  });
}

int64_t count_self_intersections(const std::vector<Triangle>& triangles,
                                 const std::vector<Vec3>& positions) {
  CrossingFinder finder;
  std::vector<TrianglePair> pairs;
  finder.find(triangles, positions, pairs);
  return static_cast<int64_t>(pairs.size());
}

}  // namespace drape
