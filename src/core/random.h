// Deterministic pseudo-random numbers from an index (splitmix64: a tiny, well-mixed hash), so
// that a perturbation or a generated shape depends on its inputs alone.
#pragma once

#include <cstdint>

namespace drape {

inline uint64_t splitmix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Uniform in [-1, 1), from a hash of `key`.
inline double uniform_from(uint64_t key) {
  return static_cast<double>(splitmix64(key) >> 11) * 0x1.0p-52 - 1.0;
}

}  // namespace drape
