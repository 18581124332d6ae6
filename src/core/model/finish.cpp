// What every generator finishes a model with: adjacency, spring colours, an id.
#include <algorithm>
#include <atomic>

#include "model/model.h"

namespace drape::model {

void colour_springs(int32_t particles, std::vector<Spring>& springs,
                    std::vector<int32_t>& colour_begin, int& independent_colours) {
  // Bit c of used[p]: colour c is taken at particle p. Bit 63 is never set: a spring that finds
  // bits 0 … 62 all taken at its ends is left over.
  constexpr int kLeftOver = 63;
  std::vector<uint64_t> used(particles, 0);
  std::vector<int> colour(springs.size());
  int colours = 0;
  bool left_over = false;
  for (size_t s = 0; s < springs.size(); ++s) {
    const uint64_t taken = used[springs[s].i] | used[springs[s].j];
    int c = 0;
    while (c < kLeftOver && (taken >> c & 1u)) ++c;
    colour[s] = c;
    if (c == kLeftOver) {
      left_over = true;
      continue;
    }
    used[springs[s].i] |= uint64_t{1} << c;
    used[springs[s].j] |= uint64_t{1} << c;
    colours = std::max(colours, c + 1);
  }
  independent_colours = colours;
  // A stable counting sort by colour, the left-over springs last.
  const int groups = colours + (left_over ? 1 : 0);
  std::vector<int32_t> count(groups + 1, 0);
  for (int& c : colour) {
    if (c == kLeftOver) c = colours;
    ++count[c + 1];
  }
  for (int c = 0; c < groups; ++c) count[c + 1] += count[c];
  colour_begin = count;
  std::vector<Spring> sorted(springs.size());
  for (size_t s = 0; s < springs.size(); ++s) sorted[count[colour[s]]++] = springs[s];
  springs = std::move(sorted);
}

void finish(ClothModel& m) {
  const int32_t n = static_cast<int32_t>(m.rest_position.size());
  m.vertex_triangle_begin.assign(n + 1, 0);
  for (const Triangle& t : m.triangles)
    for (int32_t p : t) ++m.vertex_triangle_begin[p + 1];
  for (int32_t p = 0; p < n; ++p) m.vertex_triangle_begin[p + 1] += m.vertex_triangle_begin[p];
  m.vertex_triangles.resize(m.triangles.size() * 3);
  std::vector<int32_t> fill(m.vertex_triangle_begin.begin(), m.vertex_triangle_begin.end() - 1);
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (int32_t p : m.triangles[t]) m.vertex_triangles[fill[p]++] = static_cast<int32_t>(t);

  colour_springs(n, m.springs, m.colour_begin, m.independent_colours);

  double sum = 0.0;
  int64_t count = 0;
  for (const Spring& s : m.springs) {
    if (s.kind != SpringKind::structural) continue;
    sum += s.rest;
    ++count;
  }
  m.mean_edge = count > 0 ? sum / static_cast<double>(count) : 0.0;
  static std::atomic<uint64_t> next_id{1};
  m.id = next_id++;
}

}  // namespace drape::model
