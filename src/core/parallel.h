// When a loop is worth threads. A parallel region costs a few microseconds to open; below a
// few thousand particles or springs per loop a single thread is faster, and many small regions
// per substep also fight other processes for the cores (libgomp spins while it waits).
#pragma once

#include <cstdint>
#include <vector>

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

/// The calling thread's number in its parallel region (0 outside one).
inline int thread_number() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// Lists the threads of a parallel region fill, one each, that keep their storage from one
/// region to the next: a search run every step allocates only while what it finds grows.
template <class T>
class ThreadLists {
 public:
  /// Before the region: a cleared list for each thread it may use.
  void clear() {
    if (lists_.size() < static_cast<size_t>(max_threads())) lists_.resize(max_threads());
    for (std::vector<T>& list : lists_) list.clear();
  }
  /// Inside the region: the calling thread's list.
  std::vector<T>& mine() { return lists_[thread_number()]; }
  /// After it: every list appended to `out`, in thread order.
  void gather(std::vector<T>& out) const {
    for (const std::vector<T>& list : lists_) out.insert(out.end(), list.begin(), list.end());
  }
  int64_t bytes() const {
    int64_t sum = static_cast<int64_t>(lists_.capacity() * sizeof(std::vector<T>));
    for (const std::vector<T>& list : lists_)
      sum += static_cast<int64_t>(list.capacity() * sizeof(T));
    return sum;
  }

 private:
  std::vector<std::vector<T>> lists_;
};

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
