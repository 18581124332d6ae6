#include "collision/collider_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bounded_count.h"
#include "collision/motion.h"

namespace drape {

Vec3 reference_point(const ColliderDef& d) {
  switch (d.type) {
    case ColliderType::capsule:
      return 0.5 * (d.a + d.b);
    case ColliderType::mesh:
      return d.transform.translate;
    default:
      return d.center;
  }
}

ColliderSet::ColliderSet(const std::vector<ColliderDef>& defs, double t) : defs_(defs) {
  rest_ = make_colliders(defs);
  for (const ColliderDef& d : defs_) {
    reference_.push_back(reference_point(d));
    moves_ = moves_ || d.motion.moves();
  }
  for (const Collider& c : rest_) {
    // A pose of a sweep may move the surface by half the collider's thickness across (a
    // sphere's or capsule's radius, a box's smallest half extent, half a mesh's smallest box
    // side), and never by less than the thickness kept around it.
    double across = std::numeric_limits<double>::infinity();
    if (c.type == ColliderType::sphere || c.type == ColliderType::capsule) across = c.radius;
    if (c.type == ColliderType::box) across = c.half_extents.minCoeff();
    if (c.type == ColliderType::mesh) across = 0.5 * c.bound_radius;
    size_.push_back(std::max(0.5 * across, c.thickness));
  }
  now_ = rest_;
  contact_ = rest_;
  settled_.assign(rest_.size(), Pose{});
  if (moves_) contact_.reserve(rest_.size() * kMaxSweep);
  settle(t);
}

Collider ColliderSet::posed(size_t k, const Pose& p, const Pose& start, double elapsed) const {
  Collider c = rest_[k];
  const Mat3& R = p.rotation;
  c.pose = p;
  c.center = p.apply(c.center);
  c.normal = R * c.normal;
  c.a = p.apply(c.a);
  c.b = p.apply(c.b);
  c.rotation = R * c.rotation;
  c.bound_center = p.apply(c.bound_center);
  c.moving = elapsed > 0.0;
  c.back_rotation = start.rotation * R.transpose();
  c.back_from = p.translation;
  c.back_to = start.translation;
  return c;
}

double ColliderSet::hand_along(double t) const {
  const double span = hand_t1_ - hand_t0_;
  return span > 0.0 ? std::clamp((t - hand_t0_) / span, 0.0, 1.0) : 1.0;
}

Pose ColliderSet::pose_of(size_t k, double t) const {
  Pose p = pose_at(defs_[k].motion, reference_[k], t);
  if (!hand_to_.empty())
    p.translation += hand_from_[k] + hand_along(t) * (hand_to_[k] - hand_from_[k]);
  return p;
}

void ColliderSet::hand(size_t k, const Vec3& offset, double t0, double t1) {
  if (hand_to_.empty()) {
    hand_from_.assign(rest_.size(), Vec3::Zero());
    hand_to_.assign(rest_.size(), Vec3::Zero());
    held_.assign(rest_.size(), 0);
    contact_.reserve(rest_.size() * kMaxSweep);
    moves_ = true;
  }
  // Each one starts from where it is now: the last hand's move has been completed or is cut
  // short where it stands at t0.
  const double along = hand_along(t0);
  for (size_t j = 0; j < rest_.size(); ++j) {
    hand_from_[j] += along * (hand_to_[j] - hand_from_[j]);
    hand_to_[j] = hand_from_[j];
  }
  hand_to_[k] = offset;
  held_[k] = 1;
  hand_t0_ = t0;
  hand_t1_ = t1;
}

bool ColliderSet::settle(double t) {
  bool moved = false;
  for (size_t k = 0; k < rest_.size(); ++k) {
    if (!moving(k)) continue;
    const Pose p = pose_of(k, t);
    moved = moved || p.rotation != settled_[k].rotation || p.translation != settled_[k].translation;
    settled_[k] = p;
    now_[k] = posed(k, p, p, 0.0);
  }
  if (moves_) contact_ = now_;
  return moved;
}

double ColliderSet::travel(size_t k, double t0, double t1) const {
  if (!moving(k)) return 0.0;
  const Pose start = pose_of(k, t0), end = pose_of(k, t1);
  // Its bounding sphere's centre's move, plus the turn times the radius (a sphere turning
  // about its own centre keeps its surface).
  const Vec3 centre = rest_[k].bound_center;
  double travel = (end.apply(centre) - start.apply(centre)).norm();
  if (rest_[k].type != ColliderType::sphere && std::isfinite(rest_[k].bound_radius))
    travel += Eigen::AngleAxisd(end.rotation * start.rotation.transpose()).angle() *
              rest_[k].bound_radius;
  return travel;
}

int ColliderSet::substeps_for(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                              const std::vector<double>& inv_mass, double t0, double t1,
                              Counted counted) const {
  const double dt = t1 - t0;
  double worst = 0.0;  // the most substep lengths a collider's relative move spans
  for (size_t k = 0; k < rest_.size(); ++k) {
    const bool round =
        rest_[k].type == ColliderType::sphere || rest_[k].type == ColliderType::capsule;
    if (moving(k) ? counted == Counted::still_round : !round) continue;
    const double own = moving(k) ? travel(k, t0, t1) : 0.0;
    double fastest = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
      if (inv_mass[i] == 0.0) continue;
      const double move = v[i].norm() * dt;
      if (move > fastest && !clear_of(now_[k], x[i], move + own)) fastest = move;
    }
    worst = std::max(worst, (own + fastest) / (size_[k] / kSubstepsPerPose));
  }
  return ceil_count(worst * (1.0 - 1e-9), 1, kMaxSubsteps);
}

void ColliderSet::pose(double t0, double t1) {
  if (!moves_) return;
  contact_.clear();
  for (size_t k = 0; k < rest_.size(); ++k) {
    if (!moving(k)) {
      contact_.push_back(rest_[k]);
      continue;
    }
    const Pose start = pose_of(k, t0), end = pose_of(k, t1);
    const int pieces = ceil_count(travel(k, t0, t1) / size_[k], 1, kMaxSweep);
    for (int j = 1; j <= pieces; ++j) {
      const double t = j == pieces ? t1 : t0 + (t1 - t0) * j / pieces;
      contact_.push_back(posed(k, j == pieces ? end : pose_of(k, t), start, t - t0));
      contact_.back().move_time = t - t0;
    }
    now_[k] = contact_.back();
  }
}

int64_t ColliderSet::bytes() const {
  return heap_bytes(defs_, rest_, reference_, size_, now_, contact_, settled_, hand_from_, hand_to_,
                    held_);
}

}  // namespace drape
