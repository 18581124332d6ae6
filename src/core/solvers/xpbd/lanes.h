// SIMD lanes for recurrences that run across many independent chains at once (the rows of a
// grid, the chains of a mesh's path cover): kLanes numbers as one vector, and tiles moved to and
// from them transposed in registers.
#pragma once

#include <cstring>
#include <utility>

namespace drape::xpbd {

/// kLanes numbers as one vector (GCC's and Clang's vector extensions: arithmetic is lane by lane
/// and compiles to whatever SIMD the target has), and kLanes × kLanes tiles of an array moved to
/// and from them, transposed in registers. The row solve runs its recurrences kLanes rows at a
/// time this way: a row's numbers are contiguous along it, and the transposes turn a tile of
/// them into one vector per column across the rows, without a strided load or store per number.
/// A recurrence step costs its latency whatever the vector's width, so kLanes fills a register:
/// 16 floats where the target has 512-bit vectors (AVX-512), else 8 numbers. Each lane is its own
/// row, so the width leaves the row solve's bits as they are (the columns' twist, which the row
/// groups place, may move a row, and their round-off with it).
template <typename Real>
struct Lanes {
#ifdef __AVX512F__
  static constexpr int kLanes = 64 / sizeof(Real);
#else
  static constexpr int kLanes = 8;
#endif
  typedef Real Vec __attribute__((vector_size(kLanes * sizeof(Real))));
  using Tile = Vec[kLanes];

  // Rows [0, nrows) and columns [0, ncols) of the tile whose row k starts at src + k·stride;
  // the rest of the tile is `fill`. Each of the rows is read whole, so the array needs kLanes
  // numbers of slack past the last place read. Returned transposed: tile[j] holds column j.
  static void load(const Real* src, int stride, int nrows, int ncols, Real fill, Tile& tile) {
    const Vec lane = iota(std::make_index_sequence<kLanes>()), filled = Vec{} + fill;
    for (int k = 0; k < kLanes; ++k) {
      if (k < nrows) {
        std::memcpy(&tile[k], src + k * stride, sizeof(Vec));
        if (ncols < kLanes) tile[k] = lane < Real(ncols) ? tile[k] : filled;
      } else {
        tile[k] = filled;
      }
    }
    transpose(tile);
  }
  // The inverse of load for the tile's rows [0, nrows) and columns [0, ncols); tile is
  // transposed in place.
  static void store(Tile& tile, Real* dst, int stride, int nrows, int ncols) {
    transpose(tile);
    for (int k = 0; k < nrows; ++k) std::memcpy(dst + k * stride, &tile[k], ncols * sizeof(Real));
  }

 private:
  template <size_t... I>
  static Vec iota(std::index_sequence<I...>) {
    return Vec{Real(I)...};
  }
  // Swapping the off-diagonal k × k blocks of every 2k × 2k block exchanges bit k of the row
  // and column indices; doing so for k = 1, 2, 4, … transposes the tile.
  template <int k>
  static constexpr int low(int p) {
    return (p & k) ? kLanes + p - k : p;
  }
  template <int k>
  static constexpr int high(int p) {
    return (p & k) ? kLanes + p : p + k;
  }
  template <int k, size_t... I>
  static void swap_blocks(Vec& a, Vec& b, std::index_sequence<I...>) {
    const Vec l = __builtin_shufflevector(a, b, low<k>(I)...);
    const Vec h = __builtin_shufflevector(a, b, high<k>(I)...);
    a = l;
    b = h;
  }
  template <int k>
  static void swap_all(Tile& t) {
    for (int i = 0; i < kLanes; ++i)
      if (!(i & k)) swap_blocks<k>(t[i], t[i + k], std::make_index_sequence<kLanes>());
  }
  static void transpose(Tile& t) {
    static_assert(kLanes == 8 || kLanes == 16);
    swap_all<1>(t);
    swap_all<2>(t);
    swap_all<4>(t);
    if constexpr (kLanes == 16) swap_all<8>(t);
  }
};

}  // namespace drape::xpbd
