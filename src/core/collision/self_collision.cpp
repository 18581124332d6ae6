#include "self_collision.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "closest_points.h"
#include "parallel.h"

namespace drape {

namespace {

// Gauss–Seidel passes over the contacts per frame: enough for a pile's few layers to settle at
// the thickness; what they leave crossing, the fail-safe removes.
constexpr int kContactPasses = 4;
// Pairs this many thicknesses apart at the end of the frame are kept as contacts, so a pass
// that moves a neighbour closer still finds them.
constexpr double kReach = 2.0;
// Particles this close to a collider (in thicknesses) rest on it.
constexpr double kGrounded = 0.1;
// Pairs this close (in thicknesses) at the end of the frame count as touching.
constexpr double kTouching = 1.01;
// Thicknesses layers may move relative to each other between two collision steps: further,
// and one layer passes another before a step sees them close (measured on a crumpling pile:
// 3 keeps its strain near the solver's own, 10 and more lets layers tangle).
constexpr double kMotionPerPart = 0.5;
// A crossing is certain to leave a contact where every triangle's inradius is under this share
// of the reach (crossings_leave_contacts_): the margin is far above the round-off of the
// segments' distance the edge pairs are found by.
constexpr double kCrossingReach = 0.999;
// Rounds of rigid impact zones before the last resort (zones held where they started).
constexpr int kRigidRounds = 3;
// Rounds in all: each freezing round freezes at least one more vertex, so this bound is never
// reached on a cloth whose crossings the fail-safe can remove.
constexpr int kMaxRounds = 1000;

double sign_or(double value, double otherwise) {
  return value > 0.0 ? 1.0 : value < 0.0 ? -1.0 : otherwise;
}

// The swept box of points over the frame, widened by `margin`.
template <typename... Points>
Box swept_box(double margin, const Vec3& first, const Points&... rest) {
  Box box{first, first};
  ((box.lo = box.lo.cwiseMin(rest), box.hi = box.hi.cwiseMax(rest)), ...);
  box.lo.array() -= margin;
  box.hi.array() += margin;
  return box;
}

// Which side of triangle tri's plane vertex p was on at the start of the frame (the sign of
// the result), or 0 when it was not over the triangle's face within `reach` of it then. A
// vertex beside the face may come over it from either side without passing through it; one
// far from it may reach the other side by a path no side test can follow (the fail-safe sees
// what it crosses).
double start_side(int32_t p, const Triangle& tri, const std::vector<Vec3>& start, double reach) {
  const Vec3 &a = start[tri[0]], &b = start[tri[1]], &c = start[tri[2]];
  if (!over_face(start[p], a, b, c, kFaceMargin).interior) return 0.0;
  const Vec3 normal = (b - a).cross(c - a);
  const double side = normal.dot(start[p] - a);
  return std::abs(side) < reach * normal.norm() ? side : 0.0;
}

// The offset between two edges' nearest points at the start of the frame when both lay inside
// their edges within `reach` of each other then, else zero: the direction two edges that cross
// during the frame reverse.
Vec3 start_offset(const std::array<int32_t, 2>& e, const std::array<int32_t, 2>& f,
                  const std::vector<Vec3>& start, double reach) {
  const Vec3 &p0 = start[e[0]], &p1 = start[e[1]], &q0 = start[f[0]], &q1 = start[f[1]];
  const SegmentPoints sp = closest_between_segments(p0, p1, q0, q1);
  if (!sp.interior) return Vec3::Zero();
  const Vec3 d = (1 - sp.s) * p0 + sp.s * p1 - (1 - sp.t) * q0 - sp.t * q1;
  return d.squaredNorm() < reach * reach ? d : Vec3::Zero();
}

}  // namespace

double self_collision_thickness(const SelfCollisionDef& def, const ClothModel& model) {
  return def.thickness > 0.0 ? def.thickness : 0.25 * model.mean_edge;
}

void SelfCollision::prepare(const ClothModel& model, double thickness, double friction) {
  thickness_ = thickness;
  friction_ = friction;
  edges_ = triangle_edges(model.triangles);
  threads_.clear();
  for (const Spring& s : model.springs)
    if (s.kind == SpringKind::structural) threads_.push_back({s.i, s.j});
  patches_.prepare(model, edges_);
  zone_.resize(model.size());
  std::iota(zone_.begin(), zone_.end(), 0);
  zone_state_.assign(model.size(), 0);
  zoned_.clear();
  contacts_.clear();
  near_.clear();
  held_.pairs.clear();
}

int SelfCollision::parts_for(double motion) const {
  const double parts = std::ceil(motion / (kMotionPerPart * thickness_));
  return parts >= kMaxParts ? kMaxParts : parts > 1.0 ? static_cast<int>(parts) : 1;
}

int64_t SelfCollision::bytes() const {
  return heap_bytes(edges_, face_boxes_, edge_boxes_, kept_faces_, kept_edges_, contacts_, near_,
                    solved_, held_.pairs, contacted_, mobility_, crossing_, zone_, zone_state_,
                    zoned_, boxed_, finite_, threads_, touched_threads_, thread_lengths_, touched_,
                    suspect_) +
         face_grid_.bytes() + edge_grid_.bytes() + found_.bytes() + found_near_.bytes() +
         patches_.bytes() + crossing_finder_.bytes();
}

void SelfCollision::find_contacts(const ClothModel& model, const std::vector<Vec3>& start,
                                  const std::vector<Vec3>& x) {
  const double h = thickness_, reach = kReach * h;
  const std::vector<Triangle>& triangles = model.triangles;
  // Swept boxes: a triangle's widened by the reach, so a vertex's own swept box meets it when
  // the two come within reach; an edge's by half, so two edges' boxes meet within it. The
  // triangles and the vertices share one grid (triangle t as box t, vertex p as box T + p), so
  // that each cell lists its triangles, then its vertices. The parts of the cloth smooth at the
  // end of the frame cannot pass through themselves (smooth_patches.h): what lies inside one,
  // away from every other part, is left out of the grids, and pairs inside one are skipped.
  const int32_t triangle_count = static_cast<int32_t>(triangles.size());
  const int32_t n = static_cast<int32_t>(x.size());
  patches_.update(triangles, x);
  if (patches_.whole()) {
    // The cloth is one smooth patch at the frame's end (a sheet falling or lying flat): every
    // pair would be left out as inside it, and no two of its triangles meet, so neither the
    // search nor the check for crossings has anything to find.
    contacts_.clear();
    near_.clear();
    near_motion_ = 0.0;
    crossings_leave_contacts_ = true;
    return;
  }
  // Which vertices are finite at both ends of the frame, once: asked of every triangle's and
  // edge's corners, it took about 5% of a frame of bench drape-sc at 128².
  finite_.resize(x.size());
  for (int32_t p = 0; p < n; ++p) finite_[p] = x[p].allFinite() && start[p].allFinite();
  auto finite = [&](int32_t p) { return finite_[p] != 0; };
  // The boxes, then the grids, built side by side, each by one thread (the same either way).
#pragma omp parallel sections if (worth_threads(n))
  {
#pragma omp section
    {
      face_boxes_.resize(triangles.size() + x.size());
      boxed_.assign(triangles.size(), 0);
      // Whether every triangle's inradius r is under the reach (crossings_leave_contacts_), by
      // the bound r = area / semi-perimeter ≤ area / longest edge: |ab × ac|² < 4·(reach·longest)².
      const double most = kCrossingReach * reach;
      bool small = true;
      for (int32_t t = 0; t < triangle_count; ++t) {
        const Triangle& tri = triangles[t];
        if (!finite(tri[0]) || !finite(tri[1]) || !finite(tri[2])) continue;
        face_boxes_[t] = swept_box(reach, x[tri[0]], x[tri[1]], x[tri[2]], start[tri[0]],
                                   start[tri[1]], start[tri[2]]);
        boxed_[t] = 1;
        const Vec3 ab = x[tri[1]] - x[tri[0]], ac = x[tri[2]] - x[tri[0]], bc = ac - ab;
        const double longest = std::max({ab.squaredNorm(), ac.squaredNorm(), bc.squaredNorm()});
        small = small && ab.cross(ac).squaredNorm() < 4.0 * most * most * longest;
      }
      crossings_leave_contacts_ = small;
      for (int32_t p = 0; p < n; ++p)
        if (finite(p)) face_boxes_[triangle_count + p] = swept_box(0.0, x[p], start[p]);
    }
#pragma omp section
    {
      edge_boxes_.resize(edges_.size());
      for (size_t e = 0; e < edges_.size(); ++e) {
        const auto [i, j] = edges_[e];
        if (finite(i) && finite(j))
          edge_boxes_[e] = swept_box(0.5 * reach, x[i], x[j], start[i], start[j]);
      }
    }
  }
  patches_.keep(face_boxes_, boxed_);
#pragma omp parallel sections if (worth_threads(n))
  {
#pragma omp section
    {
      kept_faces_.clear();
      for (int32_t t = 0; t < triangle_count; ++t)
        if (boxed_[t] && patches_.triangle_kept(t)) kept_faces_.push_back(t);
      for (int32_t p = 0; p < n; ++p)
        if (finite(p) && patches_.vertex_kept(p)) kept_faces_.push_back(triangle_count + p);
      face_grid_.build(face_boxes_, kept_faces_);
    }
#pragma omp section
    {
      kept_edges_.clear();
      for (size_t e = 0; e < edges_.size(); ++e) {
        const auto [i, j] = edges_[e];
        if (finite(i) && finite(j) && patches_.edge_kept(static_cast<int32_t>(e)))
          kept_edges_.push_back(static_cast<int32_t>(e));
      }
      edge_grid_.build(edge_boxes_, kept_edges_);
    }
  }

  // A vertex and a triangle are found when within reach at the end of the frame, or when the
  // vertex changed sides of the triangle's plane while over its face. A pair found is a contact
  // when its stencil has a direction there (layer_stencil); one whose nearest points lie on a
  // boundary (a vertex beside a triangle's edge, two edges whose nearest points are an end)
  // pushes nothing, and about two thirds of a pile's pairs are such: they go to near_, only to
  // mark their particles for the check for crossings.
  enum class Found { none, near, acts };
  using enum Found;
  auto acting = [](const LayerStencil& st) { return st.valid ? acts : near; };
  auto vertex_triangle = [&](int32_t p, int32_t t) {
    const Triangle& tri = triangles[t];
    if (tri[0] == p || tri[1] == p || tri[2] == p ||
        SmoothPatches::within_smooth(patches_.region_of_vertex(p), patches_.region_of_triangle(t)))
      return none;
    const Vec3 &a = x[tri[0]], &b = x[tri[1]], &c = x[tri[2]];
    const TrianglePoint q = closest_on_triangle(x[p], a, b, c);
    const Vec3 d = x[p] - (q.wa * a + q.wb * b + q.wc * c);
    const Vec3 corners[4] = {x[p], a, b, c};
    if (d.squaredNorm() < reach * reach) return acting(layer_stencil(0, corners));
    const TrianglePoint over = over_face(x[p], a, b, c, kFaceMargin);
    if (!over.interior) return none;
    const double side0 = start_side(p, tri, start, reach);
    const double side1 = (b - a).cross(c - a).dot(x[p] - a);
    return side0 * side1 < 0.0 ? acting(face_stencil(corners, over)) : none;
  };
  // Two edges likewise: within reach, or their nearest points' offset reversed.
  auto edge_edge = [&](int32_t e, int32_t f) {
    const auto [i, j] = edges_[e];
    const auto [k, l] = edges_[f];
    if (i == k || i == l || j == k || j == l ||
        SmoothPatches::within_smooth(patches_.region_of_edge(e), patches_.region_of_edge(f)))
      return none;
    const SegmentPoints sp = closest_between_segments(x[i], x[j], x[k], x[l]);
    const Vec3 d = (1 - sp.s) * x[i] + sp.s * x[j] - (1 - sp.t) * x[k] - sp.t * x[l];
    if (d.squaredNorm() < reach * reach ||
        (sp.interior && d.dot(start_offset(edges_[e], edges_[f], start, reach)) < 0.0)) {
      const Vec3 ends[4] = {x[i], x[j], x[k], x[l]};
      return acting(edge_stencil(ends, sp));  // the nearest points just found
    }
    return none;
  };

  // How far particles i and j moved relative to each other, squared.
  auto moved_past = [&](int32_t i, int32_t j) {
    return ((x[i] - start[i]) - (x[j] - start[j])).squaredNorm();
  };

  contacts_.clear();
  near_.clear();
  found_.clear();
  found_near_.clear();
  double motion = 0.0;  // the pairs' largest moved_past
#pragma omp parallel if (worth_threads(n)) reduction(max : motion)
  {
    std::vector<Contact>& mine = found_.mine();
    std::vector<Contact>& mine_near = found_near_.mine();
    auto keep = [&](Found found, const Contact& c) {
      (found == acts ? mine : mine_near).push_back(c);
    };
    // Vertex–triangle pairs cell by cell, each in the one cell the grid reports it in.
    const int64_t face_cells = face_grid_.cells();
#pragma omp for schedule(dynamic, 64) nowait
    for (int64_t cell = 0; cell < face_cells; ++cell)
      face_grid_.each_pair_across(cell, triangle_count, [&](int32_t t, int32_t p) {
        const Found found = vertex_triangle(p - triangle_count, t);
        if (found == none) return;
        keep(found, {p - triangle_count, t, 0});
        motion = std::max(motion, moved_past(p - triangle_count, triangles[t][0]));
      });
    // Edge pairs cell by cell, each pair in the one cell the grid reports it in.
    const int64_t cells = edge_grid_.cells();
#pragma omp for schedule(dynamic, 64) nowait
    for (int64_t cell = 0; cell < cells; ++cell)
      edge_grid_.each_pair_in(cell, [&](int32_t e, int32_t f) {
        const Found found = edge_edge(e, f);
        if (found == none) return;
        keep(found, {e, f, 1});
        motion = std::max(motion, moved_past(edges_[e][0], edges_[f][0]));
      });
  }
  found_.gather(contacts_);
  found_near_.gather(near_);
  near_motion_ = std::sqrt(motion);
  // The order the threads found them in varies; the order they are resolved in must not.
  std::sort(contacts_.begin(), contacts_.end(), [](const Contact& u, const Contact& w) {
    return u.kind != w.kind ? u.kind < w.kind : u.a != w.a ? u.a < w.a : u.b < w.b;
  });
}

void SelfCollision::particles_of(const Contact& c, const ClothModel& model,
                                 int32_t index[4]) const {
  if (c.kind == 0) {
    const Triangle& tri = model.triangles[c.b];
    index[0] = c.a, index[1] = tri[0], index[2] = tri[1], index[3] = tri[2];
  } else {
    index[0] = edges_[c.a][0], index[1] = edges_[c.a][1];
    index[2] = edges_[c.b][0], index[3] = edges_[c.b][1];
  }
}

SelfCollision::Stencil SelfCollision::stencil(const Contact& c, const ClothModel& model,
                                              const std::vector<Vec3>& start,
                                              const std::vector<Vec3>& x) const {
  Stencil st;
  const int32_t* index = st.index;
  particles_of(c, model, st.index);
  Vec3 p[4];
  for (int k = 0; k < 4; ++k) p[k] = x[index[k]];
  const LayerStencil layer = layer_stencil(c.kind, p);
  std::copy(layer.coef, layer.coef + 4, st.coef);
  if (!layer.valid) return st;
  Vec3 d = Vec3::Zero();
  for (int k = 0; k < 4; ++k) d += st.coef[k] * p[k];
  // Kept on the side the pair started the frame on (when it was close then): a vertex on its
  // side of the triangle's plane, two edges their nearest points' offset.
  const double reach = kReach * thickness_;
  const double start_sign =
      c.kind == 0 ? start_side(c.a, model.triangles[c.b], start, reach)
                  : layer.normal.dot(start_offset(edges_[c.a], edges_[c.b], start, reach));
  st.side = sign_or(start_sign, sign_or(layer.normal.dot(d), 1.0));
  st.dir = st.side * layer.normal;
  st.separation = st.dir.dot(d);
  st.valid = true;
  return st;
}

unsigned SelfCollision::grounded_bits(const int32_t index[4]) const {
  unsigned bits = 0;
  for (int k = 0; k < 4; ++k)
    if (mobility_[index[k]] == 0.0) bits |= 1u << k;
  return bits;
}

double SelfCollision::mobilities(const Stencil& st, const ClothState& state,
                                 double mobility[4]) const {
  double inv_mass[4];
  for (int k = 0; k < 4; ++k) inv_mass[k] = state.inv_mass[st.index[k]];
  return pair_mobilities(st.coef, inv_mass, grounded_bits(st.index), mobility);
}

void SelfCollision::push_apart(const Contact& c, const ClothModel& model,
                               const std::vector<Vec3>& start, ClothState& state) const {
  std::vector<Vec3>& x = state.x;
  const Stencil st = stencil(c, model, start, x);
  const int32_t* index = st.index;
  const double* coef = st.coef;
  const Vec3& dir = st.dir;
  const double depth = thickness_ - st.separation;
  if (!st.valid || !(depth > 0.0)) return;
  double mobility[4];
  const double weight = mobilities(st, state, mobility);
  if (!(weight > 0.0)) return;
  const double lambda = depth / weight;
  for (int k = 0; k < 4; ++k) x[index[k]] += (lambda * coef[k] * mobility[k]) * dir;

  // Coulomb friction on the pair's relative slide over the frame, as for colliders: cancelled
  // where within friction × depth (static), shortened by it otherwise (kinetic).
  if (friction_ <= 0.0) return;
  Vec3 slide = Vec3::Zero();
  for (int k = 0; k < 4; ++k) slide += coef[k] * (x[index[k]] - start[index[k]]);
  slide -= slide.dot(dir) * dir;
  const double length = slide.norm(), grip = friction_ * depth;
  if (!(length > 0.0)) return;
  const double cancel = length <= grip ? 1.0 : grip / length;
  for (int k = 0; k < 4; ++k) x[index[k]] -= (cancel * coef[k] * mobility[k] / weight) * slide;
}

void SelfCollision::find_crossings(const ClothModel& model, const std::vector<Vec3>& x) {
  if (!crossings_leave_contacts_) {
    crossing_finder_.find(model.triangles, x, crossing_);
    return;
  }
  // Every crossing at the search left an edge–edge pair (crossings_leave_contacts_), whose
  // particles are touched_; a pair of triangles none of whose corners is touched or has moved
  // since is as it was then, and so crosses only where it crossed then: never. Only pairs with
  // a triangle at a pair found or moved can cross.
  const std::vector<Triangle>& triangles = model.triangles;
  suspect_.resize(triangles.size());
  auto suspect = [&](int32_t v) { return touched_[v] != 0 || x[v] != solved_[v]; };
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    suspect_[t] = suspect(tri[0]) || suspect(tri[1]) || suspect(tri[2]);
  }
  crossing_finder_.find(triangles, x, &suspect_, crossing_);
}

bool SelfCollision::remove_crossings(const ClothModel& model, const std::vector<Vec3>& start,
                                     double dt, ClothState& state) {
  std::vector<Vec3>& x = state.x;
  find_crossings(model, x);
  report_.crossings = static_cast<int64_t>(crossing_.size());
  if (crossing_.empty()) return false;

  auto root = [&](int32_t v) {
    while (zone_[v] != v) v = zone_[v] = zone_[zone_[v]];
    return v;
  };
  // The zones' momenta are those of the motion the contacts left.
  contacted_ = x;
  for (int round = 0; round < kMaxRounds && !crossing_.empty(); ++round) {
    // Every crossing pair's six vertices join one zone.
    for (const TrianglePair& pair : crossing_) {
      const int32_t first = model.triangles[pair.s][0];
      for (const int32_t t : {pair.s, pair.t})
        for (const int32_t v : model.triangles[t]) {
          if (zone_state_[v] == 0) zone_state_[v] = 1, zoned_.push_back(v);
          const int32_t a = root(first), b = root(v);
          if (a != b) zone_[std::max(a, b)] = std::min(a, b);
        }
    }
    // The zones, each a run of zoned_ sorted by root then vertex: the same sums every time.
    std::sort(zoned_.begin(), zoned_.end(), [&](int32_t u, int32_t w) {
      const int32_t ru = root(u), rw = root(w);
      return ru != rw ? ru < rw : u < w;
    });
    const bool rigid = round < kRigidRounds;
    for (size_t z0 = 0, z1; z0 < zoned_.size(); z0 = z1) {
      const int32_t r = root(zoned_[z0]);
      bool held = false;  // frozen already, or holding a pinned or grabbed particle
      for (z1 = z0; z1 < zoned_.size() && root(zoned_[z1]) == r; ++z1)
        held = held || zone_state_[zoned_[z1]] == 2 || state.inv_mass[zoned_[z1]] == 0.0;
      if (!rigid || held) {
        for (size_t k = z0; k < z1; ++k) {
          const int32_t v = zoned_[k];
          zone_state_[v] = 2;
          if (state.inv_mass[v] == 0.0) continue;
          x[v] = start[v];
          state.v[v].setZero();
        }
        continue;
      }
      // Rigid: the zone's centre of mass moves with its momentum and it turns with its angular
      // momentum about the centre, from where it started the frame.
      double mass = 0.0;
      Vec3 centre = Vec3::Zero(), velocity = Vec3::Zero();
      for (size_t k = z0; k < z1; ++k) {
        const int32_t v = zoned_[k];
        mass += model.mass[v];
        centre += model.mass[v] * start[v];
        velocity += model.mass[v] * (contacted_[v] - start[v]) / dt;
      }
      centre /= mass;
      velocity /= mass;
      Vec3 momentum = Vec3::Zero();
      Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
      for (size_t k = z0; k < z1; ++k) {
        const int32_t v = zoned_[k];
        const Vec3 r0 = start[v] - centre;
        momentum += model.mass[v] * r0.cross((contacted_[v] - start[v]) / dt - velocity);
        inertia +=
            model.mass[v] * (r0.squaredNorm() * Eigen::Matrix3d::Identity() - r0 * r0.transpose());
      }
      // A zone in a line (or at a point) has no inertia about it: it only translates.
      const double determinant = inertia.determinant(), trace = inertia.trace();
      const Vec3 spin = determinant > 1e-9 * trace * trace * trace
                            ? Vec3(inertia.inverse() * momentum)
                            : Vec3::Zero();
      const double angle = spin.norm() * dt;
      const Eigen::Matrix3d turn =
          angle > 0.0 ? Eigen::AngleAxisd(angle, spin.normalized()).toRotationMatrix()
                      : Eigen::Matrix3d::Identity();
      const Vec3 moved = centre + dt * velocity;
      for (size_t k = z0; k < z1; ++k) {
        const int32_t v = zoned_[k];
        x[v] = moved + turn * (start[v] - centre);
        state.v[v] = velocity + spin.cross(x[v] - moved);
      }
    }
    find_crossings(model, x);
    // A round that can freeze nothing more (every crossing pair held already: pinned or held
    // particles moved into it) cannot help: what is left is reported.
    if (!rigid) {
      bool progress = false;
      for (const TrianglePair& pair : crossing_)
        for (const int32_t t : {pair.s, pair.t})
          for (const int32_t v : model.triangles[t])
            progress = progress || (zone_state_[v] != 2 && state.inv_mass[v] != 0.0);
      if (!progress) break;
    }
  }
  report_.left = static_cast<int64_t>(crossing_.size());
  for (const int32_t v : zoned_) {
    if (zone_state_[v] == 1) ++report_.zone_vertices;
    if (zone_state_[v] == 2) ++report_.frozen_vertices;
  }
  return true;
}

void SelfCollision::touch(const ClothModel& model) {
  touched_.assign(model.size(), 0);
  for (const std::vector<Contact>* pairs : {&contacts_, &near_})
    for (const Contact& c : *pairs) {
      int32_t index[4];
      particles_of(c, model, index);
      for (const int32_t v : index) touched_[v] = 1;
    }
}

void SelfCollision::gather_threads(const ClothState& state) {
  touched_threads_.clear();
  thread_lengths_.clear();
  for (int32_t k = 0; k < static_cast<int32_t>(threads_.size()); ++k) {
    const auto [i, j] = threads_[k];
    if (touched_[i] || touched_[j]) {
      touched_threads_.push_back(k);
      thread_lengths_.push_back((state.x[j] - state.x[i]).norm());
    }
  }
}

void SelfCollision::keep_lengths(ClothState& state) const {
  std::vector<Vec3>& x = state.x;
  for (size_t m = 0; m < touched_threads_.size(); ++m) {
    const auto [i, j] = threads_[touched_threads_[m]];
    const double wi = mobility_[i], wj = mobility_[j];
    const Vec3 d = x[j] - x[i];
    const double length = d.norm();
    if (!(wi + wj > 0.0) || !(length > 0.0)) continue;
    const Vec3 step = ((length - thread_lengths_[m]) / ((wi + wj) * length)) * d;
    x[i] += wi * step;
    x[j] -= wj * step;
  }
}

void SelfCollision::ground(const ClothModel& model, const ClothState& state,
                           const std::vector<Collider>& colliders) {
  // Particles resting on a collider do not give way to the layers above them (mass scaling
  // for stacks, as in Guendelman et al. 2003's shock propagation): the upper layer takes the
  // whole push, and no contact drives a lower layer into the ground.
  mobility_.resize(model.size());
  for (int32_t i = 0; i < model.size(); ++i) {
    mobility_[i] = state.inv_mass[i];
    Vec3 normal;
    for (const Collider& col : colliders)
      if (signed_distance(col, state.x[i], normal) - col.thickness < kGrounded * thickness_)
        mobility_[i] = 0.0;
  }
}

const HeldLayers& SelfCollision::hold_layers(const ClothModel& model, const ClothState& state,
                                             const std::vector<Collider>& colliders) {
  held_.thickness = thickness_;
  held_.friction = friction_;
  held_.pairs.clear();
  if (contacts_.empty()) return held_;
  ground(model, state, colliders);
  for (const Contact& c : contacts_) {
    const Stencil st = stencil(c, model, state.x, state.x);
    if (!st.valid || !(st.separation < kReach * thickness_)) continue;
    HeldLayers::Pair pair;
    pair.kind = c.kind;
    pair.side = st.side > 0.0 ? 1 : -1;
    pair.grounded = static_cast<uint8_t>(grounded_bits(st.index));
    std::copy(st.index, st.index + 4, pair.index);
    held_.pairs.push_back(pair);
  }
  return held_;
}

bool SelfCollision::resolve(const ClothModel& model, const std::vector<Vec3>& start,
                            const std::vector<Collider>& colliders, double dt, ClothState& state,
                            bool solver_held_layers) {
  report_ = {};
  solved_ = state.x;
  // Last frame's zones, undone.
  for (const int32_t v : zoned_) zone_[v] = v, zone_state_[v] = 0;
  zoned_.clear();

  find_contacts(model, start, state.x);
  report_.contacts = static_cast<int64_t>(contacts_.size() + near_.size());
  bool changed = false;
  const bool found = !contacts_.empty() || !near_.empty();
  if (found) touch(model);
  if (!contacts_.empty()) {
    changed = true;
    ground(model, state, colliders);  // before any contact moves a particle off a collider
    // Where the solver held the layers in its substeps, the pushes correct what it let
    // through, and between them the threads at the contacts go back to the lengths it left
    // (the pushes alone stretched a stiff pile's threads 2 to 4%, where the solver left 1%).
    // A method that leaves resting layers to this stage is pushed apart here every frame, and
    // there that kept an implicit pile from coming to rest (README, Self-collision).
    if (solver_held_layers) gather_threads(state);
    for (int pass = 0; pass < kContactPasses; ++pass) {
      if (pass > 0 && solver_held_layers) keep_lengths(state);
      for (const Contact& c : contacts_) push_apart(c, model, start, state);
      if (colliders.empty()) continue;
      for (int32_t i = 0; i < model.size(); ++i) {
        if (state.inv_mass[i] == 0.0) continue;
        Vec3 normal;
        for (const Collider& col : colliders) project_out(col, state.x[i], normal);
      }
    }
  }
  // The certified check for crossings, unless the search has shown there can be none: no
  // pair found, and so nothing moved since the search, which found every crossing's edge pair.
  if (found || !crossings_leave_contacts_)
    changed = remove_crossings(model, start, dt, state) || changed;
  if (!changed) return false;

  // Velocities change with what the contacts moved (rigid and frozen vertices have theirs).
  for (int32_t i = 0; i < model.size(); ++i)
    if (state.inv_mass[i] != 0.0 && zone_state_[i] == 0)
      state.v[i] += (state.x[i] - solved_[i]) / dt;
  // Pairs left touching do not approach any more (an inelastic impulse on the relative normal
  // velocity): moving the positions back does not stop a vertex the solver drove through, and
  // it would go through again next frame, against the contacts every frame. With that impulse,
  // Coulomb friction on the relative sliding velocity: the positions' friction cancels a
  // step's slide, but the solver's velocity at the step's end is the last substep's, about
  // twice the step's mean on a slope, and what is left of it would creep.
  for (const Contact& c : contacts_) {
    const Stencil st = stencil(c, model, start, state.x);
    if (!st.valid || st.separation > kTouching * thickness_) continue;
    Vec3 relative = Vec3::Zero();
    double mobility[4];
    bool zoned = false;  // zones have their velocities
    for (int k = 0; k < 4; ++k) {
      zoned = zoned || zone_state_[st.index[k]] != 0;
      relative += st.coef[k] * state.v[st.index[k]];
    }
    const double approach = -st.dir.dot(relative);
    const double weight = mobilities(st, state, mobility);
    if (zoned || !(approach > 0.0) || !(weight > 0.0)) continue;
    const Vec3 slide = relative + approach * st.dir;  // the tangential part
    const double length = slide.norm(), grip = friction_ * approach;
    const Vec3 change =
        approach * st.dir - (length > 0.0 ? std::min(1.0, grip / length) : 0.0) * slide;
    for (int k = 0; k < 4; ++k)
      state.v[st.index[k]] += (st.coef[k] * mobility[k] / weight) * change;
  }
  update_normals(model, state);
  return true;
}

}  // namespace drape
