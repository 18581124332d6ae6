// Vectors whose storage starts on a cache line. The solvers split their arrays between threads
// at multiples of 16 elements; from a plain std::vector (16-byte aligned) the line holding each
// boundary is written by both threads, and passes back and forth between their caches.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace drape {

inline constexpr std::size_t kCacheLine = 64;

template <typename T>
struct CacheAligned {
  using value_type = T;
  CacheAligned() = default;
  template <typename U>
  CacheAligned(const CacheAligned<U>&) noexcept {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{kCacheLine}));
  }
  void deallocate(T* p, std::size_t) noexcept {
    ::operator delete (p, std::align_val_t{kCacheLine});
  }
  template <typename U>
  bool operator==(const CacheAligned<U>&) const noexcept {
    return true;
  }
};

/// A std::vector whose data() is aligned to a cache line.
template <typename T>
using AlignedVector = std::vector<T, CacheAligned<T>>;

}  // namespace drape
