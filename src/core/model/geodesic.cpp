// Geodesic distances on the rest shape, from several sources at once, each particle keeping the
// k nearest: what the long-range attachments measure their rest lengths by.
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <tuple>

#include "model/model.h"

namespace drape::model {

namespace {

// The distance to c through the edge a–b of a flat triangle, from the virtual source s that lies
// at da from a and db from b on the far side of the edge from c, when the straight line s–c
// crosses that edge; infinity otherwise (the edges then give the distance). Exact on a flat or
// developable surface when da and db come from one source.
double through_edge(const Vec3& a, double da, const Vec3& b, double db, const Vec3& c) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const Vec3 ab = b - a;
  const double len = ab.norm();
  if (len == 0.0) return kInf;
  const Vec3 e1 = ab / len;
  const Vec3 ac = c - a;
  const double cx = ac.dot(e1), cy = (ac - cx * e1).norm();
  if (cy == 0.0) return kInf;
  // s = (sx, sy) in the frame with a at the origin, b at (len, 0) and c above the axis.
  const double sx = (da * da - db * db + len * len) / (2.0 * len);
  const double sy2 = da * da - sx * sx;
  if (sy2 < 0.0) return kInf;
  const double sy = -std::sqrt(sy2);
  // Where s–c crosses the axis; it must lie on the edge (up to round-off).
  const double t = sx + (cx - sx) * (-sy) / (cy - sy);
  const double slack = 1e-9 * len;
  if (t < -slack || t > len + slack) return kInf;
  return std::hypot(cx - sx, cy - sy);
}

}  // namespace

void nearest_sources(const ClothModel& model, const std::vector<int32_t>& sources, int k,
                     std::vector<int32_t>& nearest_source, std::vector<double>& distance) {
  const int32_t n = model.size();
  const std::vector<Vec3>& x = model.rest_position;
  nearest_source.assign(static_cast<size_t>(n) * k, -1);
  distance.assign(static_cast<size_t>(n) * k, 0.0);
  std::vector<int> found(n, 0);  // labels settled at each particle
  // The slot of source s's label at particle p, or −1.
  auto label = [&](int32_t p, int32_t s) {
    for (int t = 0; t < found[p]; ++t)
      if (nearest_source[static_cast<size_t>(p) * k + t] == s) return static_cast<size_t>(p) * k + t;
    return static_cast<size_t>(-1);
  };
  // Dijkstra with one label per (particle, source), each particle taking at most k of them, the
  // nearest first. An unfolding can reach a particle through a triangle whose far corner settles
  // after it, with a shorter distance than it settled at: the label is then corrected and
  // spread again (label-correcting), so a flat cloth ends with its straight lines. Ties break by
  // particle then source, so the result is deterministic.
  using Item = std::tuple<double, int32_t, int32_t>;  // distance, particle, source
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (int32_t s : sources) queue.push({0.0, s, s});
  while (!queue.empty()) {
    const auto [d, p, s] = queue.top();
    queue.pop();
    size_t slot = label(p, s);
    if (slot == static_cast<size_t>(-1)) {
      if (found[p] == k) continue;
      slot = static_cast<size_t>(p) * k + found[p]++;
      nearest_source[slot] = s;
    } else if (!(d < distance[slot] * (1.0 - 1e-12))) {
      continue;  // no shorter than what it has
    }
    distance[slot] = d;
    // Every triangle around p: its other corners u and w, each reached along its edge from p,
    // or through the edge p–w from a corner w that has a distance from s.
    for (int32_t t = model.vertex_triangle_begin[p]; t < model.vertex_triangle_begin[p + 1]; ++t) {
      const Triangle& tri = model.triangles[model.vertex_triangles[t]];
      for (int c = 0; c < 3; ++c) {
        const int32_t u = tri[c];
        if (u == p) continue;
        double best = d + (x[u] - x[p]).norm();
        const int32_t w = tri[0] + tri[1] + tri[2] - p - u;
        if (const size_t at = label(w, s); at != static_cast<size_t>(-1))
          best = std::min(best, through_edge(x[p], d, x[w], distance[at], x[u]));
        const size_t mine = label(u, s);
        if (mine != static_cast<size_t>(-1) ? best < distance[mine] * (1.0 - 1e-12) : found[u] < k)
          queue.push({best, u, s});
      }
    }
  }
  // Each particle's labels sorted by source, so that attachments are applied in one order.
  for (int32_t p = 0; p < n; ++p) {
    std::vector<std::pair<int32_t, double>> labels;
    for (int t = 0; t < found[p]; ++t)
      labels.push_back({nearest_source[static_cast<size_t>(p) * k + t],
                        distance[static_cast<size_t>(p) * k + t]});
    std::sort(labels.begin(), labels.end());
    for (int t = 0; t < found[p]; ++t) {
      nearest_source[static_cast<size_t>(p) * k + t] = labels[t].first;
      distance[static_cast<size_t>(p) * k + t] = labels[t].second;
    }
  }
}

}  // namespace drape::model
