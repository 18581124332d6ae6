// When a loop is worth threads. A parallel region costs a few microseconds to open; below a
// few thousand particles or springs per loop a single thread is faster, and many small regions
// per substep also fight other processes for the cores (libgomp spins while it waits).
#pragma once

#include <cstdint>

namespace drape {

inline constexpr int64_t kParallelMin = 8192;  ///< items per loop before threads are used

inline bool worth_threads(int64_t items) { return items >= kParallelMin; }

}  // namespace drape
