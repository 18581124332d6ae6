#include "box_grid.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

namespace drape {

namespace {

// Bits of an entry that hold the cell, above the box's: the cell's three coordinates packed,
// so the entries sort as plain integers.
constexpr int kCellKeyBits = 32;
// Cell entries per box at most, on average: a few huge boxes (a cloth torn apart by a diverging
// solver) widen the cells instead of filling memory.
constexpr int64_t kMaxEntriesPerBox = 16;

// Sorts the first `bits` bits of each value, least significant digit first (stable counting
// passes of 11 bits): a few passes over the entries instead of a comparison sort's log n, which
// was a fifth of self-collision's time.
void radix_sort(std::vector<uint64_t>& values, std::vector<uint64_t>& scratch, int bits) {
  constexpr int kDigit = 11;
  constexpr uint64_t kMask = (uint64_t{1} << kDigit) - 1;
  scratch.resize(values.size());
  for (int shift = 0; shift < bits; shift += kDigit) {
    std::array<size_t, kMask + 1> start{};
    for (const uint64_t v : values) ++start[(v >> shift) & kMask];
    size_t sum = 0;
    for (size_t& s : start) sum += std::exchange(s, sum);
    for (const uint64_t v : values) scratch[start[(v >> shift) & kMask]++] = v;
    values.swap(scratch);
  }
}

}  // namespace

uint32_t BoxGrid::coordinate(double v, int axis) const {
  const double c = std::floor((v - origin_[axis]) / cell_);
  return c >= 0.0 ? static_cast<uint32_t>(std::min(c, 4294967295.0)) : 0u;
}

void BoxGrid::build(const std::vector<Box>& boxes, const std::vector<int32_t>& kept) {
  boxes_ = &boxes;
  entry_.clear();
  box_bits_ = std::max(1, static_cast<int>(std::bit_width(boxes.size())));
  box_mask_ = (uint64_t{1} << box_bits_) - 1;
  cell_begin_.assign(1, 0);
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
  cell_ = std::max({2.0 * extent_sum / static_cast<double>(n), span * 0x1p-10, 1e-12});
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
          entry_.push_back(key(i, j, k) << box_bits_ | static_cast<uint32_t>(t));
  radix_sort(entry_, sorting_, box_bits_ + bits_[0] + bits_[1] + bits_[2]);
  cell_begin_.clear();
  for (size_t e = 0; e < entry_.size(); ++e)
    if (e == 0 || entry_[e] >> box_bits_ != entry_[e - 1] >> box_bits_)
      cell_begin_.push_back(static_cast<int64_t>(e));
  cell_begin_.push_back(static_cast<int64_t>(entry_.size()));
}

}  // namespace drape
