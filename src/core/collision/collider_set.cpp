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
    // A pose pushes a particle it has just overtaken out ahead of it while the particle lies
    // less deep than the middle of it: the step from the pose before may be at most half its
    // thickness across plus the contact thickness (the particle's gap in front of it).
    most_step_.push_back(across + c.thickness);
  }
  now_ = rest_;
  contact_ = rest_;
  settled_.assign(rest_.size(), Pose{});
  outran_.assign(rest_.size(), 0.0);
  outran_lo_.assign(rest_.size(), Vec3::Zero());
  outran_hi_.assign(rest_.size(), Vec3::Zero());
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
    hand_goal_.assign(rest_.size(), Vec3::Zero());
    held_.assign(rest_.size(), 0);
    contact_.reserve(rest_.size() * kMaxSweep);
    moves_ = true;
  }
  hand_goal_[k] = offset;
  held_[k] = 1;
  hand_leg(t0, t1);
}

void ColliderSet::hand_leg(double t0, double t1) {
  // Each one starts from where it is now: the last leg has been completed or is cut short
  // where it stands at t0.
  const double along = hand_along(t0);
  for (size_t j = 0; j < rest_.size(); ++j) {
    hand_from_[j] += along * (hand_to_[j] - hand_from_[j]);
    const Vec3 move = hand_goal_[j] - hand_from_[j];
    // A leg with time to sweep goes at most as far as one substep's sweep covers (every method
    // takes at least one a frame), so that its poses never jump; the rest follows in the next
    // legs. One without time (a panel change putting it back) is a placement.
    const double most = kMaxSweep * size_[j], length = move.norm();
    hand_to_[j] = t1 > t0 && length > most ? hand_from_[j] + move * (most / length) : hand_goal_[j];
  }
  hand_t0_ = t0;
  hand_t1_ = t1;
}

bool ColliderSet::settle(double t) {
  // A frame of the hand's leg has passed, and it goes short of where the hand put a collider:
  // the next leg starts from where it is.
  if (!hand_to_.empty() && t > hand_t0_ && hand_to_ != hand_goal_)
    hand_leg(t, t + (hand_t1_ - hand_t0_));
  std::fill(outran_.begin(), outran_.end(), 0.0);
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
  return moving(k) ? travel(k, pose_of(k, t0), pose_of(k, t1)) : 0.0;
}

double ColliderSet::travel(size_t k, const Pose& start, const Pose& end) const {
  // A pose maps x to R·(x − pivot) + pivot + T (motion.h), T the keyed translation and the
  // hand's. Between two poses T moves in a straight line and R turns by θ about the pivot, so a
  // point at distance d from the pivot moves at most |ΔT| + θ·d: the bounding sphere's centre,
  // plus θ times the radius for any shape but a sphere (a sphere turning about its own centre
  // keeps its surface). The chord between the centre's two places, which this once was,
  // falls short of its arc about a far pivot (by 36% for a half turn). Stable norms: a body
  // keyed a vast distance is reported with its distance, not as infinitely far.
  const MotionDef& motion = defs_[k].motion;
  const Vec3 pivot = motion.has_pivot ? motion.pivot : reference_[k];
  auto keyed = [&](const Pose& p) { return Vec3(p.translation - pivot + p.rotation * pivot); };
  const double turn = Eigen::AngleAxisd(end.rotation * start.rotation.transpose()).angle();
  const Collider& c = rest_[k];
  double reach = (c.bound_center - pivot).stableNorm();
  if (c.type != ColliderType::sphere && std::isfinite(c.bound_radius)) reach += c.bound_radius;
  return (keyed(end) - keyed(start)).stableNorm() + turn * reach;
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
    // Only a body that a free particle can reach this frame counts (a ball carried far from
    // the cloth took 64 substeps a frame for nothing).
    double fastest = 0.0;
    bool reached = false;
    for (size_t i = 0; i < x.size(); ++i) {
      if (inv_mass[i] == 0.0) continue;
      const double move = v[i].norm() * dt;
      if ((move > fastest || !reached) && !clear_of(now_[k], x[i], move + own)) {
        reached = true;
        fastest = std::max(fastest, move);
      }
    }
    if (reached) worst = std::max(worst, (own + fastest) / (size_[k] / kSubstepsPerPose));
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
    const double moved = travel(k, start, end);
    const int pieces = ceil_count(moved / size_[k], 1, kMaxSweep);
    const size_t first = contact_.size();
    for (int j = 1; j <= pieces; ++j) {
      const double t = j == pieces ? t1 : t0 + (t1 - t0) * j / pieces;
      contact_.push_back(posed(k, j == pieces ? end : pose_of(k, t), start, t - t0));
      contact_.back().move_time = t - t0;
    }
    now_[k] = contact_.back();
    if (moved > kMaxSweep * most_step_[k]) note_outrun(k, start, &contact_[first], pieces, moved);
  }
}

void ColliderSet::note_outrun(size_t k, const Pose& start, const Collider* poses, int pieces,
                              double moved) {
  // The box of its bounding sphere at the start and at each pose, grown by the step between
  // two poses, which its path between them strays by less than.
  const Collider& c = rest_[k];
  const Vec3 grow = Vec3::Constant(c.bound_radius + c.thickness + moved / pieces);
  Vec3 lo = start.apply(c.bound_center), hi = lo;
  for (int j = 0; j < pieces; ++j) {
    lo = lo.cwiseMin(poses[j].bound_center);
    hi = hi.cwiseMax(poses[j].bound_center);
  }
  lo -= grow;
  hi += grow;
  if (outran_[k] > 0.0) {
    lo = lo.cwiseMin(outran_lo_[k]);
    hi = hi.cwiseMax(outran_hi_[k]);
  }
  outran_[k] = std::max(outran_[k], moved);
  outran_lo_[k] = lo;
  outran_hi_[k] = hi;
}

ColliderSet::Outrun ColliderSet::outrun(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                        const std::vector<Triangle>& triangles, double dt) const {
  for (size_t k = 0; k < outran_.size(); ++k) {
    if (outran_[k] == 0.0) continue;
    for (const Triangle& t : triangles) {
      Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      for (const int32_t i : t) {
        const Vec3 reach = Vec3::Constant(v[i].norm() * dt);
        lo = lo.cwiseMin(x[i] - reach);
        hi = hi.cwiseMax(x[i] + reach);
      }
      if ((lo.array() <= outran_hi_[k].array()).all() &&
          (hi.array() >= outran_lo_[k].array()).all())
        return {static_cast<int>(k), outran_[k], kMaxSweep * most_step_[k]};
    }
  }
  return {};
}

int64_t ColliderSet::bytes() const {
  return heap_bytes(defs_, rest_, reference_, size_, most_step_, now_, contact_, settled_, outran_,
                    outran_lo_, outran_hi_, hand_from_, hand_to_, hand_goal_, held_);
}

}  // namespace drape
