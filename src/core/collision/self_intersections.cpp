#include "drape/self_intersections.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
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

// The sign of a 3×3 determinant of differences evaluated as orient3d does, where Shewchuk's
// bound on its rounding, relative to `permanent`, certifies it; 0 where it does not.
int certified_sign(double determinant, double permanent) {
  if (!(permanent > kSmallestPermanent)) return 0;
  const double bound = kOrientationBound * permanent;
  return determinant > bound ? 1 : determinant < -bound ? -1 : 0;
}

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
  return certified_sign(determinant, permanent);
}

}  // namespace

// orientation(a, b, c, d) as the cofactor expansion of det[b − a, c − a, d − a] along its last
// row, each term a difference times a minor of differences as in orient3d, so that Shewchuk's
// bound holds for it as it is, with the permanent of that expansion: det[a − d, b − d, c − d] =
// −(d − a)·n.
CertifiedPlane CertifiedPlane::of(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 f = b - a, g = c - a;
  const double fy_gz = f.y() * g.z(), fz_gy = f.z() * g.y(), fz_gx = f.z() * g.x(),
               fx_gz = f.x() * g.z(), fx_gy = f.x() * g.y(), fy_gx = f.y() * g.x();
  return {a, Vec3(fy_gz - fz_gy, fz_gx - fx_gz, fx_gy - fy_gx),
          Vec3(std::abs(fy_gz) + std::abs(fz_gy), std::abs(fz_gx) + std::abs(fx_gz),
               std::abs(fx_gy) + std::abs(fy_gx))};
}

int CertifiedPlane::side(const Vec3& d) const {
  const Vec3 e = d - a;
  return certified_sign(-e.dot(n), e.cwiseAbs().dot(m));
}

namespace {

// Whether segment pq, whose ends lie on sides side_p and side_q of triangle abc's plane,
// passes through the triangle: the rest of segment_crosses_triangle.
bool crosses_inside(int side_p, int side_q, const Vec3& p, const Vec3& q, const Vec3& a,
                    const Vec3& b, const Vec3& c) {
  if (side_p == 0 || side_q == 0 || side_p == side_q) return false;
  const int ab = orientation(p, q, a, b);
  if (ab == 0) return false;
  return orientation(p, q, b, c) == ab && orientation(p, q, c, a) == ab;
}

// Two triangles s and t cross when an edge of either passes through the other (the segment
// where two crossing triangles meet ends on such edges); they cannot when all three corners of
// one lie strictly on one side of the other's plane, where most neighbouring pairs of a smooth
// cloth end. Each corner's side of the other plane is found once, for both questions: a pair
// in a flat stretch of cloth, where no side is certain, took fourteen orientations before.
bool triangles_cross(const Vec3* s, const CertifiedPlane& ps, const Vec3* t,
                     const CertifiedPlane& pt) {
  int of_t[3], of_s[3];  // t's corners' sides of s's plane, and s's of t's
  for (int k = 0; k < 3; ++k) of_t[k] = ps.side(t[k]);
  if (of_t[0] != 0 && of_t[1] == of_t[0] && of_t[2] == of_t[0]) return false;
  for (int k = 0; k < 3; ++k) of_s[k] = pt.side(s[k]);
  if (of_s[0] != 0 && of_s[1] == of_s[0] && of_s[2] == of_s[0]) return false;
  for (int e = 0; e < 3; ++e) {
    const int f = (e + 1) % 3;
    if (crosses_inside(of_s[e], of_s[f], s[e], s[f], t[0], t[1], t[2])) return true;
    if (crosses_inside(of_t[e], of_t[f], t[e], t[f], s[0], s[1], s[2])) return true;
  }
  return false;
}

bool share_a_vertex(const Triangle& s, const Triangle& t) {
  for (int32_t i : s)
    for (int32_t j : t)
      if (i == j) return true;
  return false;
}

}  // namespace

// Both ends' sides of the plane, then the three orientations of pq with the triangle's edges
// agree; any zero means touching.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c) {
  return crosses_inside(orientation(a, b, c, p), orientation(a, b, c, q), p, q, a, b, c);
}

void CrossingFinder::find(const std::vector<Triangle>& triangles,
                          const std::vector<Vec3>& positions, const std::vector<uint8_t>* suspect,
                          std::vector<TrianglePair>& out) {
  out.clear();
  // The triangles whose corners are all finite, suspects first, then their boxes and planes,
  // shared out to the threads.
  const int32_t count = static_cast<int32_t>(triangles.size());
  auto finite = [&](int32_t t) {
    return positions[triangles[t][0]].allFinite() && positions[triangles[t][1]].allFinite() &&
           positions[triangles[t][2]].allFinite();
  };
  slot_.clear();
  for (int32_t t = 0; t < count; ++t)
    if ((!suspect || (*suspect)[t] != 0) && finite(t)) slot_.push_back(t);
  const int32_t split = static_cast<int32_t>(slot_.size());
  if (suspect)
    for (int32_t t = 0; t < count; ++t)
      if ((*suspect)[t] == 0 && finite(t)) slot_.push_back(t);
  const int64_t kept = static_cast<int64_t>(slot_.size());
  if (kept < 2 || split == 0) return;
  boxes_.resize(slot_.size());
  planes_.resize(slot_.size());
#pragma omp parallel for schedule(static) if (worth_threads(kept))
  for (int64_t k = 0; k < kept; ++k) {
    const Triangle& tri = triangles[slot_[k]];
    const Vec3 &a = positions[tri[0]], &b = positions[tri[1]], &c = positions[tri[2]];
    boxes_[k] = {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
    planes_[k] = CertifiedPlane::of(a, b, c);
  }
  kept_.resize(slot_.size());
  std::iota(kept_.begin(), kept_.end(), 0);
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
      grid_.each_pair_touching(cell, split, [&](int32_t j, int32_t k) {
        const int32_t s = slot_[j], t = slot_[k];
        if (share_a_vertex(triangles[s], triangles[t])) return;
        const Vec3 corners_s[3] = {positions[triangles[s][0]], positions[triangles[s][1]],
                                   positions[triangles[s][2]]};
        const Vec3 corners_t[3] = {positions[triangles[t][0]], positions[triangles[t][1]],
                                   positions[triangles[t][2]]};
        if (triangles_cross(corners_s, planes_[j], corners_t, planes_[k]))
          mine.push_back({std::min(s, t), std::max(s, t)});
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
