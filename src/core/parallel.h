// When a loop is worth threads. A parallel region costs a few microseconds to open; below a
// few thousand particles or springs per loop a single thread is faster, and many small regions
// per substep also fight other processes for the cores (libgomp spins while it waits).
#pragma once

#include <cstdint>

#include "drape/cloth.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace drape {

inline constexpr int64_t kParallelMin = 8192;  ///< items per loop before threads are used

inline bool worth_threads(int64_t items) { return items >= kParallelMin; }

/// Whether spring colour c of a model may be shared out to threads: one of its independent
/// colours (no two of its springs share a particle), large enough to be worth them.
inline bool colour_in_parallel(const ClothModel& m, int c) {
  return m.colour_is_independent(c) && worth_threads(m.colour_begin[c + 1] - m.colour_begin[c]);
}

/// Threads of the parallel region this is called in (1 outside one, and without OpenMP).
inline int team_size() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// Threads a parallel region may use (1 in a build without OpenMP).
inline int max_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace drape

namespace drape {

inline constexpr int kSumBlocks = 64;  ///< fixed partition of deterministic sums

/// Σ_{i<n} term(i), in parallel, with the same bits for any thread count: [0, n) is cut into
/// kSumBlocks fixed blocks, each summed in order, then the block sums in order (an OpenMP
/// reduction's combining order may vary from run to run). `term` may also update item i. T is
/// what is summed: a number, or a struct of several sums taken in one pass (T{} is its zero,
/// and it has +=).
template <class T = double, class Term>
T deterministic_sum(int64_t n, Term term) {
  T partial[kSumBlocks];
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int b = 0; b < kSumBlocks; ++b) {
    const int64_t begin = n * b / kSumBlocks, end = n * (b + 1) / kSumBlocks;
    T s{};
    for (int64_t i = begin; i < end; ++i) s += term(i);
    partial[b] = s;
  }
  T sum{};
  for (const T& p : partial) sum += p;
  return sum;
}

}  // namespace drape
