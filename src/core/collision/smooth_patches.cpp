#include "smooth_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "collision/dense_grid.h"
#include "drape/cloth.h"
#include "parallel.h"

namespace drape {

namespace {

// Relative size under which an orientation or an overlap counts as zero: far above the
// rounding of the sums it measures, far below any gap that matters.
constexpr double kRound = 1e-12;

double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// The side of the line through a and b that c lies on: +1, −1, or 0 within rounding.
int side_of(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 ab = b - a, ac = c - a;
  const double o = cross2(ab, ac), tol = kRound * ab.norm() * ac.norm();
  return o > tol ? 1 : o < -tol ? -1 : 0;
}

// Whether segments ab and cd meet (touching and overlapping within rounding count).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int s1 = side_of(a, b, c), s2 = side_of(a, b, d);
  const int s3 = side_of(c, d, a), s4 = side_of(c, d, b);
  if (s1 * s2 > 0 || s3 * s4 > 0) return false;  // one wholly on one side of the other's line
  if (s1 != 0 || s2 != 0 || s3 != 0 || s4 != 0) return true;
  // On one line: whether their stretches of it overlap.
  const Vec2 dir = b - a;
  const double length = dir.squaredNorm(), tc = dir.dot(c - a), td = dir.dot(d - a);
  const double tol = kRound * length;
  return std::max(tc, td) >= -tol && std::min(tc, td) <= length + tol;
}

// Whether the closed polygon q (its vertices in order) is simple: no two edges meet but
// neighbours at their shared corner. Edges are swept in the order of their lowest x, so that
// only those whose x ranges overlap are tested.
bool simple_polygon(const std::vector<Vec2>& q, std::vector<int32_t>& order) {
  const int32_t b = static_cast<int32_t>(q.size());
  if (b < 3) return false;
  auto next = [b](int32_t i) { return i + 1 == b ? 0 : i + 1; };
  // Neighbouring edges may meet only at their corner: not fold back along each other.
  for (int32_t i = 0; i < b; ++i) {
    const Vec2 &p = q[i], &r = q[next(i)], &s = q[next(next(i))];
    if (side_of(p, r, s) == 0 && (r - p).dot(s - r) <= 0.0) return false;
  }
  order.resize(b);
  for (int32_t i = 0; i < b; ++i) order[i] = i;
  auto lo = [&](int32_t i) { return std::min(q[i].x(), q[next(i)].x()); };
  auto hi = [&](int32_t i) { return std::max(q[i].x(), q[next(i)].x()); };
  std::sort(order.begin(), order.end(), [&](int32_t u, int32_t w) { return lo(u) < lo(w); });
  double scale = 0.0;
  for (const Vec2& p : q) scale = std::max(scale, (p - q[0]).lpNorm<Eigen::Infinity>());
  const double tol = kRound * scale;
  for (int32_t m = 0; m < b; ++m) {
    const int32_t i = order[m];
    const double reach = hi(i) + tol;
    for (int32_t k = m + 1; k < b && lo(order[k]) <= reach; ++k) {
      const int32_t j = order[k];
      if (next(i) == j || next(j) == i) continue;
      if (segments_meet(q[i], q[next(i)], q[j], q[next(j)])) return false;
    }
  }
  return true;
}

// The most cells the coarse grid of keep() has: a grid over a widely spread cloth takes wider
// cells.
constexpr int64_t kMaxCells = int64_t{1} << 21;

}  // namespace

void SmoothPatches::prepare(const ClothModel& model,
                            const std::vector<std::array<int32_t, 2>>& edges) {
  const std::vector<Triangle>& triangles = model.triangles;
  const int32_t count = static_cast<int32_t>(triangles.size());
  const int32_t edge_count = static_cast<int32_t>(edges.size());
  const int32_t vertices = model.size();
  auto edge_of = [&](int32_t i, int32_t j) {
    const std::array<int32_t, 2> e{std::min(i, j), std::max(i, j)};
    return static_cast<int32_t>(std::lower_bound(edges.begin(), edges.end(), e) - edges.begin());
  };
  // Each triangle's sides as edges, each edge's and each vertex's triangles in index order.
  side_.resize(3 * static_cast<size_t>(count));
  edge_begin_.assign(edge_count + 1, 0);
  vertex_begin_.assign(vertices + 1, 0);
  for (int32_t t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      side_[3 * t + k] = edge_of(triangles[t][k], triangles[t][(k + 1) % 3]);
      ++edge_begin_[side_[3 * t + k] + 1];
      ++vertex_begin_[triangles[t][k] + 1];
    }
  for (int32_t e = 0; e < edge_count; ++e) edge_begin_[e + 1] += edge_begin_[e];
  for (int32_t p = 0; p < vertices; ++p) vertex_begin_[p + 1] += vertex_begin_[p];
  edge_triangles_.resize(side_.size());
  vertex_triangles_.resize(side_.size());
  {
    std::vector<int32_t> at_edge(edge_begin_.begin(), edge_begin_.end() - 1);
    std::vector<int32_t> at_vertex(vertex_begin_.begin(), vertex_begin_.end() - 1);
    for (int32_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k) {
        edge_triangles_[at_edge[side_[3 * t + k]]++] = t;
        vertex_triangles_[at_vertex[triangles[t][k]]++] = t;
      }
  }
  // A particle in no triangle pairs with triangles the regions' culling cannot see: then
  // there are no regions.
  loose_ = count == 0;
  for (int32_t p = 0; p < vertices; ++p)
    loose_ = loose_ || vertex_begin_[p] == vertex_begin_[p + 1];

  // Patches: the pieces of the cloth whose rest shape lies in one cube of a grid, the cubes'
  // side doubling from level to level (an octree over the rest shape), so that each patch is
  // a part of one a level up. The lowest level's cubes hold about kPatchTriangles.
  nodes_.clear();
  levels_.clear();
  children_.clear();
  loop_.clear();
  std::vector<Vec3> centre(count);
  double area = 0.0;
  Vec3 lowest = Vec3::Constant(std::numeric_limits<double>::infinity());
  for (const Vec3& p : model.rest_position) lowest = lowest.cwiseMin(p);
  for (int32_t t = 0; t < count; ++t) {
    const Vec3 &a = model.rest_position[triangles[t][0]], &b = model.rest_position[triangles[t][1]],
               &c = model.rest_position[triangles[t][2]];
    centre[t] = (a + b + c) / 3.0 - lowest;
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  double side = count > 0 ? std::sqrt(kPatchTriangles * area / count) : 1.0;
  if (!(side > 0.0)) side = 1.0;
  std::vector<int32_t> of(count, -1), below, queue;
  std::vector<std::array<int64_t, 3>> cube(count);
  // The connected pieces of the cloth, which the top level's patches are.
  int32_t components = 0;
  for (int32_t seed = 0; seed < count; ++seed) {
    if (of[seed] >= 0) continue;
    of[seed] = components++;
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size(); ++head)
      for (int k = 0; k < 3; ++k) {
        const int32_t e = side_[3 * queue[head] + k];
        for (int32_t m = edge_begin_[e]; m < edge_begin_[e + 1]; ++m)
          if (of[edge_triangles_[m]] < 0)
            of[edge_triangles_[m]] = of[seed], queue.push_back(edge_triangles_[m]);
      }
  }
  roots_.clear();
  for (int level = 0;; ++level, side *= 2.0) {
    for (int32_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k)
        cube[t][k] = static_cast<int64_t>(std::floor(centre[t][k] / side));
    // The pieces: triangles of one cube joined across shared edges.
    const int32_t first = patches();
    std::vector<int32_t> members;
    members.reserve(count);
    std::fill(of.begin(), of.end(), -1);
    for (int32_t seed = 0; seed < count; ++seed) {
      if (of[seed] >= 0) continue;
      Node node;
      node.level = level;
      node.begin = static_cast<int32_t>(members.size());
      node.child_begin = static_cast<int32_t>(children_.size());
      of[seed] = patches();
      queue.assign(1, seed);
      for (size_t head = 0; head < queue.size(); ++head) {
        const int32_t t = queue[head];
        members.push_back(t);
        if (level > 0 && std::find(children_.begin() + node.child_begin, children_.end(),
                                   below[t]) == children_.end())
          children_.push_back(below[t]);
        for (int k = 0; k < 3; ++k) {
          const int32_t e = side_[3 * t + k];
          for (int32_t m = edge_begin_[e]; m < edge_begin_[e + 1]; ++m) {
            const int32_t u = edge_triangles_[m];
            if (of[u] < 0 && cube[u] == cube[t]) of[u] = patches(), queue.push_back(u);
          }
        }
      }
      node.end = static_cast<int32_t>(members.size());
      node.child_end = static_cast<int32_t>(children_.size());
      nodes_.push_back(node);
    }
    levels_.push_back(std::move(members));
    for (int32_t id = first; id < patches(); ++id) find_loop(triangles, nodes_[id]);
    below = of;
    // The top: one patch for each connected piece of the cloth.
    if (patches() - first == components) {
      roots_.clear();
      for (int32_t id = first; id < patches(); ++id) roots_.push_back(id);
      break;
    }
  }
  node_smooth_.assign(nodes_.size(), 0);
}

void SmoothPatches::find_loop(const std::vector<Triangle>& triangles, Node& node) {
  node.loop_begin = node.loop_end = static_cast<int32_t>(loop_.size());
  if (loose_) return;
  std::vector<std::array<int32_t, 3>> uses;  // edge, from, to
  std::vector<std::pair<int32_t, int32_t>> boundary;
  std::vector<int32_t> corners;
  const std::vector<int32_t>& level = levels_[node.level];
  for (int32_t m = node.begin; m < node.end; ++m) {
    const int32_t t = level[m];
    for (int k = 0; k < 3; ++k) {
      uses.push_back({side_[3 * t + k], triangles[t][k], triangles[t][(k + 1) % 3]});
      corners.push_back(triangles[t][k]);
    }
  }
  std::sort(uses.begin(), uses.end());
  std::sort(corners.begin(), corners.end());
  const int64_t vertex_count = std::unique(corners.begin(), corners.end()) - corners.begin();
  int64_t edge_total = 0;
  for (size_t a = 0; a < uses.size();) {
    size_t z = a;
    while (z < uses.size() && uses[z][0] == uses[a][0]) ++z;
    ++edge_total;
    if (z - a == 1) {
      boundary.emplace_back(uses[a][1], uses[a][2]);
    } else if (z - a != 2 || uses[a][1] != uses[a + 1][2]) {
      return;  // in more than two triangles, or run one way by both: not a disk wound one way
    }
    a = z;
  }
  if (vertex_count - edge_total + (node.end - node.begin) != 1 || boundary.empty()) return;
  // One loop: every corner of it leaves by one edge, and walking it visits every edge.
  std::sort(boundary.begin(), boundary.end());
  for (size_t a = 1; a < boundary.size(); ++a)
    if (boundary[a].first == boundary[a - 1].first) return;
  const int32_t start = boundary.front().first;
  int32_t at = start;
  for (size_t step = 0; step < boundary.size(); ++step) {
    loop_.push_back(at);
    const auto it = std::lower_bound(boundary.begin(), boundary.end(),
                                     std::pair<int32_t, int32_t>{at, INT32_MIN});
    if (it == boundary.end() || it->first != at) break;
    at = it->second;
    if (at == start && step + 1 < boundary.size()) break;
  }
  if (at != start || loop_.size() - node.loop_begin != boundary.size()) {
    loop_.resize(node.loop_begin);
    return;
  }
  node.loop_end = static_cast<int32_t>(loop_.size());
}

bool SmoothPatches::smooth(const Node& node, const std::vector<Vec3>& x) const {
  const int32_t loop_size = node.loop_end - node.loop_begin;
  if (loop_size == 0) return false;
  const std::vector<int32_t>& level = levels_[node.level];
  Vec3 sum = Vec3::Zero();
  for (int32_t m = node.begin; m < node.end; ++m) sum += normal_[level[m]];
  const double nn = sum.squaredNorm();
  if (!(nn > 0.0) || !std::isfinite(nn)) return false;
  // Every normal within the cone: n·N ≥ cos(angle)·|n|·|N|, squared.
  const double cosine = std::cos(kConeAngle * std::numbers::pi / 180.0);
  const double least = cosine * cosine * nn;
  for (int32_t m = node.begin; m < node.end; ++m) {
    const Vec3& n = normal_[level[m]];
    const double d = n.dot(sum);
    if (!(d > 0.0) || d * d < least * n.squaredNorm()) return false;
  }
  // The boundary projected along N onto the plane through its first corner.
  const Vec3 axis = sum / std::sqrt(nn);
  Eigen::Index smallest;
  axis.cwiseAbs().minCoeff(&smallest);
  const Vec3 e1 = axis.cross(Vec3::Unit(smallest)).normalized(), e2 = axis.cross(e1);
  thread_local std::vector<Vec2> projected;
  thread_local std::vector<int32_t> order;
  projected.resize(loop_size);
  const Vec3& origin = x[loop_[node.loop_begin]];
  for (int32_t m = 0; m < loop_size; ++m) {
    const Vec3 r = x[loop_[node.loop_begin + m]] - origin;
    projected[m] = Vec2(r.dot(e1), r.dot(e2));
  }
  return simple_polygon(projected, order);
}

void SmoothPatches::update(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x) {
  const int32_t count = static_cast<int32_t>(triangles.size());
  region_.assign(count, -1);
  vertex_region_.assign(vertex_begin_.size() - 1, -1);
  edge_region_.assign(edge_begin_.size() - 1, -1);
  regions_ = in_regions_ = 0;
  if (loose_) return;
  normal_.resize(count);
#pragma omp parallel for schedule(static) if (worth_threads(count))
  for (int32_t t = 0; t < count; ++t) {
    const Triangle& tri = triangles[t];
    normal_[t] = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
  }
  // From the top down: a smooth patch is a region, the parts of one that is not are tried.
  frontier_ = roots_;
  while (!frontier_.empty()) {
    const int32_t size = static_cast<int32_t>(frontier_.size());
#pragma omp parallel for schedule(dynamic, 1) if (worth_threads(count) && size > 1)
    for (int32_t k = 0; k < size; ++k) node_smooth_[frontier_[k]] = smooth(nodes_[frontier_[k]], x);
    next_.clear();
    for (int32_t id : frontier_) {
      const Node& node = nodes_[id];
      if (node_smooth_[id]) {
        for (int32_t m = node.begin; m < node.end; ++m) region_[levels_[node.level][m]] = id;
        ++regions_;
        in_regions_ += node.end - node.begin;
      } else {
        next_.insert(next_.end(), children_.begin() + node.child_begin,
                     children_.begin() + node.child_end);
      }
    }
    std::swap(frontier_, next_);
  }
  if (regions_ == 0) return;
  if (whole()) {  // every vertex and edge in the one region (none is loose)
    std::fill(vertex_region_.begin(), vertex_region_.end(), region_[0]);
    std::fill(edge_region_.begin(), edge_region_.end(), region_[0]);
    return;
  }
  auto common = [&](const std::vector<int32_t>& begin, const std::vector<int32_t>& list,
                    int32_t i) {
    const int32_t r = region_[list[begin[i]]];
    for (int32_t m = begin[i] + 1; m < begin[i + 1]; ++m)
      if (region_[list[m]] != r) return -1;
    return r;
  };
  const int32_t vertices = static_cast<int32_t>(vertex_region_.size());
  const int32_t edges = static_cast<int32_t>(edge_region_.size());
#pragma omp parallel if (worth_threads(count))
  {
#pragma omp for schedule(static) nowait
    for (int32_t p = 0; p < vertices; ++p)
      vertex_region_[p] = common(vertex_begin_, vertex_triangles_, p);
#pragma omp for schedule(static)
    for (int32_t e = 0; e < edges; ++e) edge_region_[e] = common(edge_begin_, edge_triangles_, e);
  }
}

void SmoothPatches::keep(const std::vector<Box>& face_boxes, const std::vector<uint8_t>& boxed) {
  const int32_t count = static_cast<int32_t>(region_.size());
  const int32_t vertices = static_cast<int32_t>(vertex_region_.size());
  const int32_t edge_count = static_cast<int32_t>(edge_region_.size());
  triangle_kept_.assign(count, 1);
  vertex_kept_.assign(vertices, 1);
  edge_kept_.assign(edge_count, 1);
  // With no region, or a triangle without a box (its particles not finite), everything.
  if (regions_ == 0 || std::find(boxed.begin(), boxed.begin() + count, 0) != boxed.begin() + count)
    return;
  // The coarse grid: cells as wide as a triangle's box on average, over the boxes' bounds.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double mean = 0.0;
  for (int32_t t = 0; t < count; ++t) {
    lo = lo.cwiseMin(face_boxes[t].lo);
    hi = hi.cwiseMax(face_boxes[t].hi);
    mean += (face_boxes[t].hi - face_boxes[t].lo).maxCoeff();
  }
  double cell = mean / count;
  if (!(cell > 0.0) || !std::isfinite(cell)) return;
  const Eigen::Array3i dims = dense_grid_dims(hi - lo, cell, kMaxCells);
  auto cells_of = [&](const Box& b, Eigen::Array3i& a, Eigen::Array3i& z) {
    a = dense_grid_cell(b.lo, lo, cell, dims);
    z = dense_grid_cell(b.hi, lo, cell, dims);
  };
  auto index = [&](int i, int j, int k) {
    return (static_cast<int64_t>(k) * dims.y() + j) * dims.x() + i;
  };
  cells_.assign(dims.cast<int64_t>().prod(), -1);
  for (int32_t t = 0; t < count; ++t) {
    Eigen::Array3i a, z;
    const int32_t r = region_[t] >= 0 ? region_[t] : -2;
    cells_of(face_boxes[t], a, z);
    for (int k = a.z(); k <= z.z(); ++k)
      for (int j = a.y(); j <= z.y(); ++j)
        for (int i = a.x(); i <= z.x(); ++i) {
          int32_t& mark = cells_[index(i, j, k)];
          mark = mark == -1 || mark == r ? r : -2;
        }
  }
#pragma omp parallel for schedule(static) if (worth_threads(count))
  for (int32_t t = 0; t < count; ++t) {
    Eigen::Array3i a, z;
    bool mixed = region_[t] < 0;
    cells_of(face_boxes[t], a, z);
    for (int k = a.z(); k <= z.z() && !mixed; ++k)
      for (int j = a.y(); j <= z.y() && !mixed; ++j)
        for (int i = a.x(); i <= z.x() && !mixed; ++i) mixed = cells_[index(i, j, k)] == -2;
    triangle_kept_[t] = mixed;
  }
  auto any_kept = [&](const std::vector<int32_t>& begin, const std::vector<int32_t>& list,
                      int32_t i) {
    for (int32_t m = begin[i]; m < begin[i + 1]; ++m)
      if (triangle_kept_[list[m]]) return uint8_t{1};
    return uint8_t{0};
  };
  for (int32_t p = 0; p < vertices; ++p)
    vertex_kept_[p] = any_kept(vertex_begin_, vertex_triangles_, p);
  for (int32_t e = 0; e < edge_count; ++e)
    edge_kept_[e] = any_kept(edge_begin_, edge_triangles_, e);
}

int32_t SmoothPatches::disks() const {
  return static_cast<int32_t>(std::count_if(
      nodes_.begin(), nodes_.end(), [](const Node& n) { return n.loop_end > n.loop_begin; }));
}

int64_t SmoothPatches::bytes() const {
  int64_t levels = 0;
  for (const auto& level : levels_) levels += heap_bytes(level);
  return levels + heap_bytes(nodes_, children_, roots_, loop_, side_, edge_begin_, edge_triangles_,
                             vertex_begin_, vertex_triangles_, vertex_region_, edge_region_,
                             normal_, region_, frontier_, next_, node_smooth_, cells_,
                             triangle_kept_, vertex_kept_, edge_kept_);
}

}  // namespace drape
