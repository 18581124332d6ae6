// A count (substeps, pieces, iterations) from a real estimate, clamped before it is cast: a
// vast or infinite estimate (a body keyed to move 1e12 m in a frame) would overflow the cast.
#pragma once

#include <cmath>

namespace drape {

/// The least integer ≥ v, within [lo, hi]; hi where v is not a number (err toward more).
inline int ceil_count(double v, int lo, int hi) {
  if (std::isnan(v) || v >= hi) return hi;
  if (v <= lo) return lo;
  return static_cast<int>(std::ceil(v));
}

}  // namespace drape
