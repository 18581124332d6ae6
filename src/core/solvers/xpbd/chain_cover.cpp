#include "chain_cover.h"

#include <algorithm>
#include <tuple>

namespace drape::xpbd {

namespace {

// Two edges continue each other through a particle when the angle between them is at least
// 120° (a turn of at most 60°).
constexpr double kStraightEnough = -0.5;

}  // namespace

ChainCover cover_with_chains(const std::vector<Vec3>& x,
                             const std::vector<std::pair<int32_t, int32_t>>& edges,
                             int max_layers, int min_length) {
  const int32_t n = static_cast<int32_t>(x.size());
  const int32_t m = static_cast<int32_t>(edges.size());
  // The edges at each particle.
  std::vector<int32_t> begin(n + 1, 0), at(2 * static_cast<size_t>(m));
  for (const auto& [i, j] : edges) {
    ++begin[i + 1];
    ++begin[j + 1];
  }
  for (int32_t p = 0; p < n; ++p) begin[p + 1] += begin[p];
  {
    std::vector<int32_t> fill(begin.begin(), begin.end() - 1);
    for (int32_t e = 0; e < m; ++e) {
      at[fill[edges[e].first]++] = e;
      at[fill[edges[e].second]++] = e;
    }
  }
  auto other = [&](int32_t e, int32_t p) {
    return edges[e].first == p ? edges[e].second : edges[e].first;
  };
  // partner[2e + s]: the edge that continues edge e through its end s (0: first, 1: second),
  // or −1. At each particle the pairs are taken most opposite first.
  std::vector<int32_t> partner(2 * static_cast<size_t>(m), -1);
  auto end_of = [&](int32_t e, int32_t p) { return 2 * e + (edges[e].first == p ? 0 : 1); };
  std::vector<std::tuple<double, int32_t, int32_t>> pairs;
  for (int32_t p = 0; p < n; ++p) {
    pairs.clear();
    for (int32_t a = begin[p]; a < begin[p + 1]; ++a)
      for (int32_t b = a + 1; b < begin[p + 1]; ++b) {
        const Vec3 da = (x[other(at[a], p)] - x[p]).normalized();
        const Vec3 db = (x[other(at[b], p)] - x[p]).normalized();
        const double c = da.dot(db);
        if (c <= kStraightEnough) pairs.push_back({c, at[a], at[b]});
      }
    std::sort(pairs.begin(), pairs.end());
    for (const auto& [c, a, b] : pairs) {
      const int32_t ea = end_of(a, p), eb = end_of(b, p);
      if (partner[ea] >= 0 || partner[eb] >= 0) continue;
      partner[ea] = b;
      partner[eb] = a;
    }
  }
  // Trails: follow the partners from an edge end that has none (open trails first, then what
  // is left, cycles, each cut where it was entered).
  std::vector<uint8_t> walked(m, 0);
  std::vector<std::vector<int32_t>> trails;  // as particle sequences
  auto walk = [&](int32_t e, int32_t from) {
    std::vector<int32_t> trail{from};
    int32_t p = from;
    while (e >= 0 && !walked[e]) {
      walked[e] = 1;
      const int32_t q = other(e, p);
      trail.push_back(q);
      e = partner[end_of(e, q)];
      p = q;
    }
    trails.push_back(std::move(trail));
  };
  for (int32_t e = 0; e < m; ++e)
    for (int s = 0; s < 2; ++s)
      if (!walked[e] && partner[2 * e + s] < 0)
        walk(e, s == 0 ? edges[e].first : edges[e].second);
  for (int32_t e = 0; e < m; ++e)
    if (!walked[e]) walk(e, edges[e].first);
  std::stable_sort(trails.begin(), trails.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });

  // Lay each trail into layers: in layer f the runs of its particles still free there become
  // chains (a particle met twice in a run ends it), and what a layer cannot take goes on to the
  // next. Edges past the last layer, or in runs shorter than min_length, are left over.
  ChainCover cover;
  std::vector<std::vector<uint8_t>> used;
  std::vector<uint8_t> in_run(n, 0);
  std::vector<std::pair<int32_t, int32_t>> left;  // particle pairs, matched to edges below
  for (const std::vector<int32_t>& trail : trails) {
    // Whole, in the first layer where all its particles are free (and it meets none twice): so
    // that a grid-like mesh's rows fill one layer and its columns the next, rather than each
    // layer holding pieces of both.
    bool placed = false;
    if (static_cast<int>(trail.size()) - 1 >= min_length) {
      bool simple = true;
      for (int32_t p : trail) simple = simple && !in_run[p]++;
      for (int32_t p : trail) in_run[p] = 0;
      for (int f = 0; simple && f < max_layers && !placed; ++f) {
        if (f == static_cast<int>(used.size())) {
          used.emplace_back(n, 0);
          cover.layers.emplace_back();
        }
        if (std::any_of(trail.begin(), trail.end(), [&](int32_t p) { return used[f][p] != 0; }))
          continue;
        for (int32_t p : trail) used[f][p] = 1;
        cover.layers[f].push_back(trail);
        placed = true;
      }
    }
    if (placed) continue;
    std::vector<std::vector<int32_t>> pieces{trail};
    for (int f = 0; f < max_layers && !pieces.empty(); ++f) {
      if (f == static_cast<int>(used.size())) {
        used.emplace_back(n, 0);
        cover.layers.emplace_back();
      }
      std::vector<std::vector<int32_t>> rest;
      for (const std::vector<int32_t>& piece : pieces) {
        // Edge k joins piece[k] and piece[k + 1]; a run of edges whose particles are free in
        // this layer (and not met twice) becomes a chain if long enough.
        std::vector<uint8_t> taken(piece.size(), 0);
        size_t start = 0;  // the run's first particle
        auto close = [&](size_t end) {  // the run is piece[start .. end]
          for (size_t k = start; k <= end; ++k) in_run[piece[k]] = 0;
          if (end >= start + static_cast<size_t>(min_length)) {
            for (size_t k = start; k <= end; ++k) used[f][piece[k]] = 1;
            for (size_t k = start; k < end; ++k) taken[k] = 1;
            cover.layers[f].emplace_back(piece.begin() + start, piece.begin() + end + 1);
          }
        };
        bool open = false;
        for (size_t k = 0; k + 1 < piece.size(); ++k) {
          const int32_t a = piece[k], b = piece[k + 1];
          if (open && !used[f][b] && !in_run[b]) {
            in_run[b] = 1;
            continue;
          }
          if (open) close(k);
          open = !used[f][a] && !used[f][b];
          if (open) {
            start = k;
            in_run[a] = in_run[b] = 1;
          }
        }
        if (open) close(piece.size() - 1);
        // The edges this layer did not take, in their runs, go on to the next.
        for (size_t k = 0; k + 1 < piece.size(); ++k) {
          if (taken[k]) continue;
          if (k == 0 || taken[k - 1]) rest.push_back({piece[k]});
          rest.back().push_back(piece[k + 1]);
        }
      }
      pieces = std::move(rest);
    }
    for (const std::vector<int32_t>& piece : pieces)
      for (size_t k = 0; k + 1 < piece.size(); ++k) left.push_back({piece[k], piece[k + 1]});
  }
  while (!cover.layers.empty() && cover.layers.back().empty()) cover.layers.pop_back();
  // The left-over pairs as edge indices.
  std::vector<std::pair<std::pair<int32_t, int32_t>, int32_t>> index(m);
  for (int32_t e = 0; e < m; ++e)
    index[e] = {{std::min(edges[e].first, edges[e].second),
                 std::max(edges[e].first, edges[e].second)},
                e};
  std::sort(index.begin(), index.end());
  for (const auto& [a, b] : left) {
    const std::pair<int32_t, int32_t> key{std::min(a, b), std::max(a, b)};
    const auto it = std::lower_bound(index.begin(), index.end(), std::make_pair(key, int32_t{-1}));
    if (it != index.end() && it->first == key) cover.left_over.push_back(it->second);
  }
  std::sort(cover.left_over.begin(), cover.left_over.end());
  return cover;
}

}  // namespace drape::xpbd
