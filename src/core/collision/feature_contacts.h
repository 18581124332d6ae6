// Contacts between the cloth and the sharp features of boxes and closed meshes
// (sharp_features.h): a collider edge against the cloth's edges, a collider corner against the
// cloth's triangles, the two pairs through which a convex body can pass into a cloth whose
// particles all lie outside it (the vertex–face and edge–edge pairs of cloth contact, the
// body's side being the features').
//
// A cloth edge that lies across a collider edge (not wholly beyond either of its faces' planes)
// keeps its point nearest that edge at least the thickness beyond it, along the edge's outward
// direction; a cloth triangle over a collider corner (the corner's projection inside it, the
// triangle not wholly beyond any of the corner's face planes) keeps the thickness above the
// corner along its normal. Each is pushed out at that point, the push shared between its
// particles by their weights there and inverse masses, as the triangle contacts of round
// bodies are (triangle_contact.h).
//
// An open (two-sided) mesh is thin: a particle can pass through it within one step, further
// than its thickness, and particle contacts then hold it out on the far side. The particles
// within the margin (below) of it at the frame's start keep the side they started on: one
// whose path since (in the body's frame) passes through a triangle is put back to the
// thickness on that side, as a push of its own, before the features' pushes.
//
// Which pairs can meet is found once per frame (gather): the cloth's edges and triangles whose
// boxes at the frame's start, widened by a margin for what the frame can move them, overlap a
// feature's. The margin is twice the distance the fastest particle covers in the frame at its
// start velocity plus gravity's, the thickness, and the collider's own travel; a frame whose
// particles moved farther (check) doubles it from the next frame on.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "collision/closest_points.h"
#include "collision/dense_grid.h"
#include "collision/point_push.h"
#include "collision/sharp_features.h"
#include "collision/triangle_shape.h"
#include "drape/cloth.h"
#include "drape/collider.h"

namespace drape {

/// The push that keeps cloth edge p–q at `gap` beyond collider edge e, or false where it needs
/// none or they cannot meet (all in one frame); s is the pushed point's place along p–q.
bool edge_edge_push(const SharpFeatures::Edge& e, const Vec3& p, const Vec3& q, double gap,
                    double& s, Vec3& n, double& depth);
/// The side of corner c the triangle x0 x1 x2 over it lies on along its own normal
/// (x1 − x0)×(x2 − x0): +1 or −1, or 0 (undecided) where the triangle lies within half the gap
/// of the corner or the corner's projection on it falls outside it.
int corner_side(const SharpFeatures::Corner& c, const Vec3& x0, const Vec3& x1, const Vec3& x2,
                double gap);
/// The push that keeps triangle x0 x1 x2 at `gap` beyond corner c (its face normals
/// faces[0 .. c.count)) on `side` (corner_side at the frame's start; 0: the side the corner
/// points to, where the corner is at most `reach` beyond the triangle: how far the two can
/// have moved towards each other in the frame), or false where it needs none or they cannot
/// meet (all in one frame); w are the weights of the corner's projection on the triangle. A
/// triangle that lay beside the body past the corner at the frame's start (a cloth on the
/// ground round a box's foot) stays there.
bool corner_triangle_push(const SharpFeatures::Corner& c, const Vec3* faces, const Vec3& x0,
                          const Vec3& x1, const Vec3& x2, double gap, double reach, int side,
                          double w[3], Vec3& n, double& depth);

class FeatureContacts {
 public:
  /// Sets up for the cloth's edges and triangles.
  void prepare(const ClothModel& model);

  /// Finds the pairs that can meet in the frame ahead of dt (s). `colliders` are posed at the
  /// frame's start, `travel` (m) is how far each one's surface moves at most in the frame.
  void gather(const std::vector<Collider>& colliders, const std::vector<double>& travel,
              const ClothState& state, const Vec3& gravity, double dt);
  /// After the frame: widens the next frames' margin if a particle moved farther than this
  /// frame's allowed for.
  void check(const std::vector<Vec3>& x);
  /// Whether any pair was found for this frame.
  bool any() const { return pairs_ > 0; }
  int64_t pairs() const { return pairs_; }

  /// Applies every pair's push against the colliders posed for this substep (a sweep's poses
  /// included): `cloth` gives position(i) and inv_mass(i) of particle i and carries out
  /// push(PointPush, collider). Serial: pairs share particles.
  template <class Cloth>
  void apply(const std::vector<Collider>& colliders, Cloth& cloth) const;

  int64_t bytes() const;

 private:
  // A corner, a cloth triangle and the side the triangle lay on at the frame's start.
  struct CornerPair {
    int32_t corner, triangle;
    int side;
  };
  // An open mesh, a particle near it at the frame's start and where it was (mesh's frame).
  struct SheetPair {
    const TriangleShape* mesh;
    int32_t particle;
    Vec3 start;
  };
  // A uniform grid over some features' boxes (definition frame), as lists of their indices
  // per cell over the box around them all.
  struct Grid {
    Vec3 origin = Vec3::Zero(), top = Vec3::Zero();
    double cell = 1.0;
    Eigen::Array3i dims = Eigen::Array3i::Zero();
    std::vector<int32_t> begin, entries;
    /// Enters the boxes [lo[k], hi[k]] for k in [first, first + count).
    void build(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi, int32_t first,
               int32_t count, double min_cell);
    /// Calls f(k) for every entry of the cells [lo, hi] meets (a feature once per cell, or
    /// every entry where that is fewer).
    template <class F>
    void query(const Vec3& lo, const Vec3& hi, F&& f) const;
  };
  // A collider's features with the cloth's edges (edge_pairs: feature edge, cloth edge) and
  // triangles that can meet them this frame.
  struct Group {
    std::shared_ptr<const SharpFeatures> features;
    std::vector<std::pair<int32_t, int32_t>> edge_pairs;
    std::vector<CornerPair> corner_pairs;
    Grid edge_grid, corner_grid;  ///< edges as 0.., corners after them
    std::vector<Vec3> lo, hi;     ///< each feature's box
    double reach = 0.0;           ///< m, how far the cloth and the body can near in the frame
    std::vector<int32_t> seen;
    /// 1 for a feature within another collider's thickness (a box's foot on the ground): the
    /// cloth cannot reach it, and pushed from it the cloth would be pinched between the two.
    std::vector<uint8_t> hidden;
  };
  Group& group_for(const std::shared_ptr<const SharpFeatures>& features);
  const Group* find(const SharpFeatures* features) const;
  void gather(Group& g, double margin, double gap);
  /// Marks collider k's features that lie in other colliders (posed as `colliders`).
  void hide(const std::vector<Collider>& colliders, size_t k, Group& g);

  std::vector<std::array<int32_t, 2>> edges_;
  std::vector<Triangle> triangles_;
  std::vector<Group> groups_;
  std::vector<SheetPair> sheet_pairs_;
  std::vector<Vec3> start_, local_;
  double mean_edge_ = 0.0;
  double allowed_ = 0.0;  ///< m, the motion this frame's margin allowed for
  double boost_ = 1.0;
  int64_t pairs_ = 0;
};

template <class Cloth>
void FeatureContacts::apply(const std::vector<Collider>& colliders, Cloth& cloth) const {
  if (pairs_ == 0) return;
  for (const Collider& c : colliders) {
    if (!c.mesh || c.mesh->closed() || sheet_pairs_.empty()) continue;
    const Mat3& R = c.pose.rotation;
    PointPush push;
    push.count = 1;
    for (const SheetPair& pair : sheet_pairs_) {
      if (pair.mesh != c.mesh.get()) continue;
      const int32_t i = pair.particle;
      const Vec3 now = R.transpose() * (cloth.position(i) - c.pose.translation);
      if (!c.mesh->crossed_by(pair.start, now)) continue;
      Vec3 n;
      push.depth = c.mesh->signed_distance(now, n) + c.thickness;
      push.index[0] = i;
      push.n = -(R * n);
      cloth.push(push, c);
    }
  }
  for (const Collider& c : colliders) {
    const Group* g = c.features ? find(c.features.get()) : nullptr;
    if (!g) continue;
    // In the features' (definition) frame; the push's direction turned back into the world.
    const Mat3& R = c.pose.rotation;
    auto local = [&](int32_t i) {
      return Vec3(R.transpose() * (cloth.position(i) - c.pose.translation));
    };
    const SharpFeatures& f = *g->features;
    PointPush push;
    for (const auto& [j, e] : g->edge_pairs) {
      const int32_t p = edges_[e][0], q = edges_[e][1];
      double s = 0.0;
      if (!edge_edge_push(f.edges[j], local(p), local(q), c.thickness, s, push.n, push.depth))
        continue;
      push.count = 2;
      push.index[0] = p, push.index[1] = q;
      push.w[0] = 1.0 - s, push.w[1] = s;
      push.n = R * push.n;
      cloth.push(push, c);
    }
    for (const CornerPair& pair : g->corner_pairs) {
      const SharpFeatures::Corner& corner = f.corners[pair.corner];
      const Triangle& tri = triangles_[pair.triangle];
      // (data(): a sheet's rim corners have no face normals, and the list may be empty.)
      if (!corner_triangle_push(corner, f.face_normals.data() + corner.first, local(tri[0]),
                                local(tri[1]), local(tri[2]), c.thickness, g->reach, pair.side,
                                push.w, push.n, push.depth))
        continue;
      push.count = 3;
      for (int k = 0; k < 3; ++k) push.index[k] = tri[k];
      push.n = R * push.n;
      cloth.push(push, c);
    }
  }
}

template <class F>
void FeatureContacts::Grid::query(const Vec3& lo, const Vec3& hi, F&& f) const {
  if (dims.x() == 0 || (hi.array() < origin.array()).any() || (lo.array() > top.array()).any())
    return;
  const Eigen::Array3i a = dense_grid_cell(lo, origin, cell, dims);
  const Eigen::Array3i b = dense_grid_cell(hi, origin, cell, dims);
  if ((b - a + 1).cast<int64_t>().prod() > int64_t(entries.size())) {  // cheaper to read all
    for (int32_t k : entries) f(k);
    return;
  }
  for (int l = a.z(); l <= b.z(); ++l)
    for (int j = a.y(); j <= b.y(); ++j)
      for (int i = a.x(); i <= b.x(); ++i) {
        const int64_t c = (int64_t(l) * dims.y() + j) * dims.x() + i;
        for (int32_t e = begin[c]; e < begin[c + 1]; ++e) f(entries[e]);
      }
}

}  // namespace drape
