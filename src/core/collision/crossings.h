// Which triangles of a cloth cross one another: the certified test behind
// count_self_intersections, as a list self-collision's fail-safe acts on.
#pragma once

#include <cstdint>
#include <vector>

#include "box_grid.h"
#include "drape/cloth.h"
#include "drape/mesh.h"
#include "parallel.h"

namespace drape {

/// Whether segment pq passes through the inside of triangle abc (p and q strictly on opposite
/// sides of its plane, the line strictly inside its three edges; touching is not crossing),
/// by certified orientation tests: a yes or no it gives is never wrong by rounding.
bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                              const Vec3& c);

/// Triangle abc's plane made once for many certified side tests: side(d) is the sign
/// orientation(a, b, c, d) certifies (which side of the plane d lies on; 0 when on it or too
/// near for doubles to tell), in a third of its arithmetic, the minors of the triangle's normal
/// n = (b − a) × (c − a) and their permanents m being made here.
struct CertifiedPlane {
  Vec3 a, n, m;
  static CertifiedPlane of(const Vec3& a, const Vec3& b, const Vec3& c);
  int side(const Vec3& d) const;
};

/// Two triangles by index, s < t.
struct TrianglePair {
  int32_t s, t;
};

/// Finds the crossing pairs count_self_intersections counts (see there for what crossing
/// means), keeping its arrays from one call to the next.
class CrossingFinder {
 public:
  /// Sets `out` to every crossing pair, sorted, the same for any thread count.
  void find(const std::vector<Triangle>& triangles, const std::vector<Vec3>& positions,
            std::vector<TrianglePair>& out) {
    find(triangles, positions, nullptr, out);
  }
  /// The same for the pairs with at least one triangle t where suspect[t] is non-zero, when the
  /// caller knows that no other pair can cross: only the cells that hold a suspect are searched.
  void find(const std::vector<Triangle>& triangles, const std::vector<Vec3>& positions,
            const std::vector<uint8_t>* suspect, std::vector<TrianglePair>& out);
  /// Heap bytes its arrays hold (for memory reports).
  int64_t bytes() const {
    return heap_bytes(boxes_, planes_, slot_, kept_) + grid_.bytes() + found_.bytes();
  }

 private:
  /// Box and plane k are triangle slot_[k]'s: the suspects' first (all of them when none is
  /// named), so that the grid tells their pairs by index; triangles with a non-finite corner
  /// are left out.
  std::vector<Box> boxes_;
  std::vector<CertifiedPlane> planes_;
  std::vector<int32_t> slot_;
  std::vector<int32_t> kept_;  ///< 0 … slot_.size() − 1, as the grid takes them
  BoxGrid grid_;
  ThreadLists<TrianglePair> found_;
};

}  // namespace drape
