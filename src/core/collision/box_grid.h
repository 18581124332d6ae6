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
  /// while it grows. `boxes` must stay as they are while the grid is read.
  void build(const std::vector<Box>& boxes, const std::vector<int32_t>& kept);

  /// Calls f(s, t) for every pair of boxes that overlap and that cell c reports (each
  /// overlapping pair in one cell only), s entered before t in the cell (s < t).
  template <class F>
  void each_pair_in(int64_t c, F&& f) const {
    pairs(c, cell_begin_[c], cell_begin_[c + 1], cell_begin_[c + 1], f, true);
  }
  /// The same for the pairs of a box below `split` with one at or above it.
  template <class F>
  void each_pair_across(int64_t c, int32_t split, F&& f) const {
    const int64_t begin = cell_begin_[c], end = cell_begin_[c + 1];
    int64_t middle = begin;
    while (middle < end && entry(middle) < split) ++middle;
    pairs(c, begin, middle, end, f, false);
  }
  /// The same for the pairs of which at least one box is below `split`; a cell with none
  /// is passed over before its boxes are read.
  template <class F>
  void each_pair_touching(int64_t c, int32_t split, F&& f) const {
    const int64_t begin = cell_begin_[c], end = cell_begin_[c + 1];
    if (entry(begin) >= split) return;
    int64_t middle = begin;
    while (middle < end && entry(middle) < split) ++middle;
    pairs(c, begin, middle, end, f, true);
  }

  int64_t bytes() const {
    return static_cast<int64_t>(cell_lo_.capacity() * sizeof(Cell) * 2 +
                                (entry_.capacity() + sorting_.capacity()) * sizeof(uint64_t) +
                                cell_begin_.capacity() * sizeof(int64_t));
  }
  int64_t entries() const { return static_cast<int64_t>(entry_.size()); }
  int64_t cells() const { return static_cast<int64_t>(cell_begin_.size()) - 1; }
  /// Cell c's boxes are entry(e) for e in [cell_begin(c), cell_begin(c + 1)).
  int64_t cell_begin(int64_t c) const { return cell_begin_[c]; }
  int32_t entry(int64_t e) const { return static_cast<int32_t>(entry_[e] & box_mask_); }
  uint64_t cell_key(int64_t c) const { return entry_[cell_begin_[c]] >> box_bits_; }

 private:
  /// f(s, t) for the entries u in [begin, middle) and w in [middle, end) of cell c, or w after
  /// u when `within`, whose boxes overlap and which c reports: the cell of the low corner of
  /// their overlap, one both entered, so that a pair meets once. Every box in c has its low
  /// corner's cell at or below c's on each axis, so c is the overlap's on an axis where one of
  /// the two boxes starts in c's slab: a bit per axis (`starts`) tells it.
  ///
  /// The cell's boxes are first copied side by side (each thread its own copy), so that the
  /// tests of one box against the rest run as one vectorised loop whose hits are then visited:
  /// tested one by one, with a branch each and the boxes read where they lie, they took most of
  /// self-collision's search. The copies only grow, as the grid's own arrays do: a frame
  /// allocates only for a cell fuller than any before on its thread. Two boxes overlap where
  /// lo ≤ the other's hi on every axis. Flags and bits are as wide as the corners (64 bits), so
  /// that the loop vectorises: with bytes GCC left it scalar.
  template <class F>
  void pairs(int64_t c, int64_t begin, int64_t middle, int64_t end, F& f, bool within) const {
    const int32_t count = static_cast<int32_t>(end - begin);
    const int32_t first_w = static_cast<int32_t>(middle - begin);
    thread_local std::vector<double> corners;
    thread_local std::vector<int32_t> ids;
    thread_local std::vector<int64_t> starts, hit;
    corners.resize(6 * static_cast<size_t>(count));
    ids.resize(count);
    starts.resize(count);
    hit.resize(count);
    // The lower corners' x, y, z, then the upper ones', each `count` long.
    double* const lx = corners.data();
    double* const ly = lx + count;
    double* const lz = ly + count;
    double* const hx = lz + count;
    double* const hy = hx + count;
    double* const hz = hy + count;
    const Cell here = cell_of(cell_key(c));
    const Box* box = boxes_->data();
    for (int32_t k = 0; k < count; ++k) {
      const int32_t t = entry(begin + k);
      ids[k] = t;
      lx[k] = box[t].lo.x(), ly[k] = box[t].lo.y(), lz[k] = box[t].lo.z();
      hx[k] = box[t].hi.x(), hy[k] = box[t].hi.y(), hz[k] = box[t].hi.z();
      const Cell& lo = cell_lo_[t];
      starts[k] = int64_t{lo[0] == here[0]} | int64_t{lo[1] == here[1]} << 1 |
                  int64_t{lo[2] == here[2]} << 2;
    }
    const int64_t* const start = starts.data();
    int64_t* const reported = hit.data();
    for (int32_t u = 0; u < first_w; ++u) {
      const double ax = lx[u], ay = ly[u], az = lz[u], bx = hx[u], by = hy[u], bz = hz[u];
      const int64_t su = start[u];
      const int32_t w0 = within ? u + 1 : first_w;
#pragma omp simd
      for (int32_t w = w0; w < count; ++w)
        reported[w] = (ax <= hx[w]) & (lx[w] <= bx) & (ay <= hy[w]) & (ly[w] <= by) &
                      (az <= hz[w]) & (lz[w] <= bz) & ((su | start[w]) == 7);
      const int32_t s = ids[u];
      for (int32_t w = w0; w < count; ++w)
        if (reported[w]) f(s, ids[w]);
    }
  }
  uint32_t coordinate(double v, int axis) const;
  Cell coordinates(const Vec3& p) const {
    return {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
  }
  uint64_t key(uint32_t i, uint32_t j, uint32_t k) const {
    return (((uint64_t{i} << bits_[1]) | j) << bits_[2]) | k;
  }
  Cell cell_of(uint64_t key) const {
    const uint64_t k = key & ((uint64_t{1} << bits_[2]) - 1);
    const uint64_t j = (key >> bits_[2]) & ((uint64_t{1} << bits_[1]) - 1);
    return {static_cast<uint32_t>(key >> (bits_[1] + bits_[2])), static_cast<uint32_t>(j),
            static_cast<uint32_t>(k)};
  }

  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> bits_{};  ///< of each coordinate in a key
  Cell last_{};                ///< the cell of the entered boxes' largest corner
  std::vector<Cell> cell_lo_, cell_hi_;
  int box_bits_ = 0;  ///< bits of an entry that hold the box (the low ones)
  uint64_t box_mask_ = 0;
  std::vector<uint64_t> entry_;    ///< cell key << box_bits_ | box, sorted
  std::vector<uint64_t> sorting_;  ///< radix sort's second buffer
  std::vector<int64_t> cell_begin_;
  const std::vector<Box>* boxes_ = nullptr;  ///< as given to the last build
};

}  // namespace drape
