// Dense grids of cubic cells laid over a box, every cell in one array: the coarse grids of
// smooth_patches.cpp and feature_contacts.cpp. Sized and indexed in double, so that no
// coordinate overflows an int, whatever the input: pieces of cloth or of a body far apart span
// more cells than an int counts before the cells are widened.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "drape/math.h"

namespace drape {

/// The cells per axis (floor(span / cell) + 1) of a grid of `cell`-wide cells over a box
/// `span` wide, the cell doubled until there are at most `max_cells` (≥ 1). Where the span or
/// the cell is not a finite positive size (coordinates near the largest double, whose
/// differences overflow), one cell of infinite width.
inline Eigen::Array3i dense_grid_dims(const Vec3& span, double& cell, int64_t max_cells) {
  if (!span.allFinite() || !std::isfinite(cell) || !(cell > 0.0)) {
    cell = std::numeric_limits<double>::infinity();
    return Eigen::Array3i::Ones();
  }
  for (;;) {
    const Eigen::Array3d dims = (span / cell).array().floor() + 1.0;
    if (dims.prod() <= static_cast<double>(max_cells)) return dims.cast<int>();
    cell *= 2.0;
  }
}

/// The cell of such a grid (corner `origin`) that holds p, clamped into the grid: a point
/// outside it (or not finite) takes the nearest cell (the first where the offset is not a
/// number).
inline Eigen::Array3i dense_grid_cell(const Vec3& p, const Vec3& origin, double cell,
                                      const Eigen::Array3i& dims) {
  Eigen::Array3i c;
  for (int k = 0; k < 3; ++k) {
    const double v = std::floor((p[k] - origin[k]) / cell);
    c[k] = v >= 0.0 ? static_cast<int>(std::min(v, static_cast<double>(dims[k] - 1))) : 0;
  }
  return c;
}

}  // namespace drape
