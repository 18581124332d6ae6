#include "drape/self_intersections.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

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

// Segment pq passes through the inside of triangle abc: p and q strictly on opposite sides of
// its plane, and the line pq strictly inside all three of its edges (the three orientations
// of pq with the edges agree). Any zero means touching, which is not crossing.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c) {
  const int side_p = orientation(a, b, c, p), side_q = orientation(a, b, c, q);
  if (side_p == 0 || side_q == 0 || side_p == side_q) return false;
  const int ab = orientation(p, q, a, b);
  if (ab == 0) return false;
  return orientation(p, q, b, c) == ab && orientation(p, q, c, a) == ab;
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

struct Box {
  Vec3 lo, hi;
};

bool overlap(const Box& a, const Box& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

using Cell = std::array<uint32_t, 3>;

// Bits of an entry that hold the cell, above the triangle's 32: the cell's three coordinates
// packed, so the entries sort as plain integers.
constexpr int kCellKeyBits = 32;
// Cell entries per triangle at most, on average: a few huge triangles (a cloth torn apart by a
// diverging solver) widen the cells instead of filling memory.
constexpr int64_t kMaxEntriesPerTriangle = 16;

// The uniform grid: cell (i, j, k) covers origin + cell·[i, i+1) × [j, j+1) × [k, k+1).
struct Grid {
  Vec3 origin;
  double cell = 1.0;
  std::array<int, 3> bits{};  ///< of each coordinate in a key

  uint32_t coordinate(double v, int axis) const {
    const double c = std::floor((v - origin[axis]) / cell);
    return static_cast<uint32_t>(std::clamp(c, 0.0, 4294967295.0));
  }
  Cell coordinates(const Vec3& p) const {
    return {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
  }
  uint64_t key(uint32_t i, uint32_t j, uint32_t k) const {
    return (((uint64_t{i} << bits[1]) | j) << bits[2]) | k;
  }
};

}  // namespace

int64_t count_self_intersections(const std::vector<Triangle>& triangles,
                                 const std::vector<Vec3>& positions) {
  // Boxes of the triangles whose corners are all finite.
  std::vector<int32_t> kept;
  std::vector<Box> boxes(triangles.size());
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Box all{Vec3::Constant(kInfinity), Vec3::Constant(-kInfinity)};
  double extent_sum = 0.0;
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Vec3 &a = positions[triangles[t][0]], &b = positions[triangles[t][1]],
               &c = positions[triangles[t][2]];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    boxes[t] = {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
    all.lo = all.lo.cwiseMin(boxes[t].lo);
    all.hi = all.hi.cwiseMax(boxes[t].hi);
    extent_sum += (boxes[t].hi - boxes[t].lo).maxCoeff();
    kept.push_back(static_cast<int32_t>(t));
  }
  const int64_t n = static_cast<int64_t>(kept.size());
  const double span = n > 0 ? (all.hi - all.lo).maxCoeff() : 0.0;
  // Nothing can cross where every corner is at one point (or there is no pair).
  if (n < 2 || !(span > 0.0) || !std::isfinite(span)) return 0;

  // Cells as wide as a mean triangle, so a typical triangle enters at most eight; widened
  // while the cells' coordinates would not fit a key or the entries would be too many.
  Grid grid{all.lo, std::max(extent_sum / static_cast<double>(n), span * 0x1p-10)};
  std::vector<Cell> cell_lo(triangles.size()), cell_hi(triangles.size());
  int64_t entries = 0;
  for (;;) {
    const Cell last = grid.coordinates(all.hi);
    for (int axis = 0; axis < 3; ++axis) grid.bits[axis] = std::bit_width(last[axis]);
    entries = 0;
    for (int32_t t : kept) {
      cell_lo[t] = grid.coordinates(boxes[t].lo);
      cell_hi[t] = grid.coordinates(boxes[t].hi);
      entries += int64_t{cell_hi[t][0] - cell_lo[t][0] + 1} * (cell_hi[t][1] - cell_lo[t][1] + 1) *
                 (cell_hi[t][2] - cell_lo[t][2] + 1);
    }
    if (grid.bits[0] + grid.bits[1] + grid.bits[2] <= kCellKeyBits &&
        entries <= kMaxEntriesPerTriangle * n)
      break;
    grid.cell *= 2.0;
  }

  // Every entry, cell key above triangle, sorted: by cell, then triangle, whatever the threads.
  std::vector<uint64_t> cell_triangles;
  cell_triangles.reserve(static_cast<size_t>(entries));
  for (int32_t t : kept)
    for (uint32_t i = cell_lo[t][0]; i <= cell_hi[t][0]; ++i)
      for (uint32_t j = cell_lo[t][1]; j <= cell_hi[t][1]; ++j)
        for (uint32_t k = cell_lo[t][2]; k <= cell_hi[t][2]; ++k)
          cell_triangles.push_back(grid.key(i, j, k) << 32 | static_cast<uint32_t>(t));
  std::sort(cell_triangles.begin(), cell_triangles.end());
  std::vector<int64_t> cell_begin;
  for (size_t e = 0; e < cell_triangles.size(); ++e)
    if (e == 0 || cell_triangles[e] >> 32 != cell_triangles[e - 1] >> 32)
      cell_begin.push_back(static_cast<int64_t>(e));
  cell_begin.push_back(static_cast<int64_t>(cell_triangles.size()));

  // Each pair in each cell they share; a pair is tested only in the cell holding the low
  // corner of the overlap of their boxes (one of the cells both entered), so it counts once.
  const int64_t cells = static_cast<int64_t>(cell_begin.size()) - 1;
  int64_t count = 0;  // an integer sum: the same in any order, so for any thread count
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : count) if (worth_threads(entries))
  for (int64_t cell = 0; cell < cells; ++cell) {
    const uint64_t key = cell_triangles[cell_begin[cell]] >> 32;
    for (int64_t e = cell_begin[cell]; e < cell_begin[cell + 1]; ++e) {
      const int32_t s = static_cast<int32_t>(cell_triangles[e] & 0xffffffffu);
      for (int64_t f = e + 1; f < cell_begin[cell + 1]; ++f) {
        const int32_t t = static_cast<int32_t>(cell_triangles[f] & 0xffffffffu);
        if (!overlap(boxes[s], boxes[t]) || share_a_vertex(triangles[s], triangles[t])) continue;
        // The low corner's cell: floor is monotonic, so it is the larger low cell of the two.
        const Cell &a = cell_lo[s], &b = cell_lo[t];
        if (grid.key(std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])) != key)
          continue;
        const Vec3 corners_s[3] = {positions[triangles[s][0]], positions[triangles[s][1]],
                                   positions[triangles[s][2]]};
        const Vec3 corners_t[3] = {positions[triangles[t][0]], positions[triangles[t][1]],
                                   positions[triangles[t][2]]};
        if (apart(corners_s, corners_t) || apart(corners_t, corners_s)) continue;
        if (triangles_cross(corners_s, corners_t)) ++count;
      }
    }
  }
  return count;
}

}  // namespace drape
