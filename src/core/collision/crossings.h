// Which triangles of a cloth cross one another: the certified test behind
// count_self_intersections, as a list self-collision's fail-safe acts on.
#pragma once

#include <cstdint>
#include <vector>

#include "box_grid.h"
#include "drape/mesh.h"

namespace drape {

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
            std::vector<TrianglePair>& out);

 private:
  std::vector<Box> boxes_;
  std::vector<int32_t> kept_;
  BoxGrid grid_;
};

}  // namespace drape
