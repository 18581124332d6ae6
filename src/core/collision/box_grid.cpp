#include "box_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace drape {

namespace {

// Bits of an entry that hold the cell, above the box's 32: the cell's three coordinates
// packed, so the entries sort as plain integers.
constexpr int kCellKeyBits = 32;
// Cell entries per box at most, on average: a few huge boxes (a cloth torn apart by a diverging
// solver) widen the cells instead of filling memory.
constexpr int64_t kMaxEntriesPerBox = 16;

}  // namespace

uint32_t BoxGrid::coordinate(double v, int axis) const {
  const double c = std::floor((v - origin_[axis]) / cell_);
  // NaN (a query box of a diverged particle) goes to cell 0, where overlap() rejects it.
  return c >= 0.0 ? static_cast<uint32_t>(std::min(c, 4294967295.0)) : 0u;
}

void BoxGrid::build(const std::vector<Box>& boxes, const std::vector<int32_t>& kept) {
  entry_.clear();
  cell_begin_.assign(1, 0);
  cell_keys_.clear();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  Box all{Vec3::Constant(kInfinity), Vec3::Constant(-kInfinity)};
  double extent_sum = 0.0;
  for (int32_t t : kept) {
    all.lo = all.lo.cwiseMin(boxes[t].lo);
    all.hi = all.hi.cwiseMax(boxes[t].hi);
    extent_sum += (boxes[t].hi - boxes[t].lo).maxCoeff();
  }
  const int64_t n = static_cast<int64_t>(kept.size());
  const double span = n > 0 ? (all.hi - all.lo).maxCoeff() : 0.0;
  if (n == 0 || !std::isfinite(span)) return;

  // Cells as wide as a mean box (and never so narrow that the coordinates overflow a key), then
  // widened while the cells' coordinates would not fit a key or the entries would be too many.
  origin_ = all.lo;
  cell_ = std::max({extent_sum / static_cast<double>(n), span * 0x1p-10, 1e-12});
  if (cell_lo_.size() < boxes.size()) {
    cell_lo_.resize(boxes.size());
    cell_hi_.resize(boxes.size());
  }
  int64_t entries = 0;
  for (;;) {
    last_ = coordinates(all.hi);
    for (int axis = 0; axis < 3; ++axis) bits_[axis] = std::bit_width(last_[axis]);
    entries = 0;
    for (int32_t t : kept) {
      cell_lo_[t] = coordinates(boxes[t].lo);
      cell_hi_[t] = coordinates(boxes[t].hi);
      entries += int64_t{cell_hi_[t][0] - cell_lo_[t][0] + 1} *
                 (cell_hi_[t][1] - cell_lo_[t][1] + 1) * (cell_hi_[t][2] - cell_lo_[t][2] + 1);
    }
    if (bits_[0] + bits_[1] + bits_[2] <= kCellKeyBits && entries <= kMaxEntriesPerBox * n) break;
    cell_ *= 2.0;
  }

  entry_.reserve(static_cast<size_t>(entries));
  for (int32_t t : kept)
    for (uint32_t i = cell_lo_[t][0]; i <= cell_hi_[t][0]; ++i)
      for (uint32_t j = cell_lo_[t][1]; j <= cell_hi_[t][1]; ++j)
        for (uint32_t k = cell_lo_[t][2]; k <= cell_hi_[t][2]; ++k)
          entry_.push_back(key(i, j, k) << 32 | static_cast<uint32_t>(t));
  std::sort(entry_.begin(), entry_.end());
  cell_begin_.clear();
  for (size_t e = 0; e < entry_.size(); ++e)
    if (e == 0 || entry_[e] >> 32 != entry_[e - 1] >> 32) {
      cell_begin_.push_back(static_cast<int64_t>(e));
      cell_keys_.push_back(entry_[e] >> 32);
    }
  cell_begin_.push_back(static_cast<int64_t>(entry_.size()));
}

int64_t BoxGrid::find_cell(uint64_t key) const {
  const auto it = std::lower_bound(cell_keys_.begin(), cell_keys_.end(), key);
  return it != cell_keys_.end() && *it == key ? it - cell_keys_.begin() : -1;
}

}  // namespace drape
