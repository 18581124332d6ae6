// FNV-1a over 64-bit words: a cheap key that tells whether what a solver built its tables from
// has changed (not a cryptographic hash; a collision would only keep stale tables).
#pragma once

#include <cstdint>
#include <cstring>

namespace drape {

struct Fnv1a {
  uint64_t key = 1469598103934665603ull;
  void mix(uint64_t v) { key = (key ^ v) * 1099511628211ull; }
  void mix_bits(double d) {
    uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    mix(u);
  }
};

}  // namespace drape
