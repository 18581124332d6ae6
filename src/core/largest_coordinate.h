// How far from the origin a set of points lies, coordinate by coordinate: what the rounding of
// a position grows with (a float or a double keeps a fixed number of digits of it), for the
// solvers that must know whether their precision resolves a cloth where it stands.
#pragma once

#include <algorithm>
#include <vector>

#include "drape/math.h"

namespace drape {

/// The largest magnitude of any coordinate of `points` (0 for none).
inline double largest_coordinate(const std::vector<Vec3>& points) {
  double most = 0.0;
  for (const Vec3& p : points) most = std::max(most, p.cwiseAbs().maxCoeff());
  return most;
}

}  // namespace drape
