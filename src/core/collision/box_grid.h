// The broad phase shared by the self-intersection count and self-collision: which axis-aligned
// boxes overlap, found through a uniform grid instead of by testing every pair.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "drape/math.h"

namespace drape {

struct Box {
  Vec3 lo, hi;
};

inline bool overlap(const Box& a, const Box& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

/// Boxes entered in the cells of a uniform grid they overlap: cell (i, j, k) covers
/// origin + cell·[i, i+1) × [j, j+1) × [k, k+1). Cells are about as wide as a mean box, so a
/// typical box enters at most eight, and work grows with the boxes and the pairs that share a
/// cell, not with their square. Entries are sorted by cell, then box, so everything read from
/// the grid comes in the same order whatever the threads.
class BoxGrid {
 public:
  using Cell = std::array<uint32_t, 3>;

  /// Enters boxes[i] for every i in `kept` (boxes with finite corners); the others are never
  /// reported. Keeps its arrays for the next build, so a grid rebuilt every frame allocates only
  /// while it grows.
  void build(const std::vector<Box>& boxes, const std::vector<int32_t>& kept);

  int64_t bytes() const {
    return static_cast<int64_t>(
        cell_lo_.capacity() * sizeof(Cell) * 2 + entry_.capacity() * sizeof(uint64_t) +
        cell_begin_.capacity() * sizeof(int64_t) + cell_keys_.capacity() * sizeof(uint64_t));
  }
  int64_t entries() const { return static_cast<int64_t>(entry_.size()); }
  int64_t cells() const { return static_cast<int64_t>(cell_begin_.size()) - 1; }
  /// Cell c's boxes are entry(e) for e in [cell_begin(c), cell_begin(c + 1)).
  int64_t cell_begin(int64_t c) const { return cell_begin_[c]; }
  int32_t entry(int64_t e) const { return static_cast<int32_t>(entry_[e] & 0xffffffffu); }
  uint64_t cell_key(int64_t c) const { return entry_[cell_begin_[c]] >> 32; }

  /// Whether cell c is the one where boxes s and t (both entered, overlapping) are reported:
  /// the cell of the low corner of their overlap, one both entered, so a pair meets once.
  bool reports_pair_in(int64_t c, int32_t s, int32_t t) const {
    const Cell &a = cell_lo_[s], &b = cell_lo_[t];
    return key(std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])) == cell_key(c);
  }

  /// Calls f(j) once for each entered box j that overlaps `box`, in increasing cell order.
  template <typename F>
  void query(const Box& box, const std::vector<Box>& boxes, F&& f) const {
    if (entry_.empty()) return;
    const Cell lo = coordinates(box.lo);
    Cell hi = coordinates(box.hi);
    double span = 1.0;
    for (int a = 0; a < 3; ++a) {
      hi[a] = std::min(hi[a], last_[a]);
      if (lo[a] > hi[a]) return;
      span *= double(hi[a] - lo[a] + 1);
    }
    if (span > double(cells())) {
      // A box wider than the grid holds (a particle flung far away): each entered box once,
      // from the entry in its own first cell.
      for (int64_t e = 0; e < entries(); ++e) {
        const int32_t t = entry(e);
        const Cell& b = cell_lo_[t];
        if (entry_[e] >> 32 == key(b[0], b[1], b[2]) && overlap(box, boxes[t])) f(t);
      }
      return;
    }
    for (uint32_t i = lo[0]; i <= hi[0]; ++i)
      for (uint32_t j = lo[1]; j <= hi[1]; ++j)
        for (uint32_t k = lo[2]; k <= hi[2]; ++k) {
          const int64_t c = find_cell(key(i, j, k));
          if (c < 0) continue;
          for (int64_t e = cell_begin_[c]; e < cell_begin_[c + 1]; ++e) {
            const int32_t t = entry(e);
            if (!overlap(box, boxes[t])) continue;
            // Report t in the first cell both boxes share (the low corner of the overlap).
            const Cell& b = cell_lo_[t];
            if (std::max(lo[0], b[0]) != i || std::max(lo[1], b[1]) != j ||
                std::max(lo[2], b[2]) != k)
              continue;
            f(t);
          }
        }
  }

 private:
  uint32_t coordinate(double v, int axis) const;
  Cell coordinates(const Vec3& p) const {
    return {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
  }
  uint64_t key(uint32_t i, uint32_t j, uint32_t k) const {
    // Out of the grid's range (a query box beyond every entered box): a key no cell has.
    if (i > last_[0] || j > last_[1] || k > last_[2]) return ~uint64_t{0};
    return (((uint64_t{i} << bits_[1]) | j) << bits_[2]) | k;
  }
  int64_t find_cell(uint64_t key) const;

  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> bits_{};  ///< of each coordinate in a key
  Cell last_{};                ///< the largest coordinates of any entered box
  std::vector<Cell> cell_lo_, cell_hi_;
  std::vector<uint64_t> entry_;  ///< cell key << 32 | box, sorted
  std::vector<int64_t> cell_begin_;
  std::vector<uint64_t> cell_keys_;  ///< each cell's key, for find_cell
};

}  // namespace drape
