// The scene's colliders over time: each posed by its motion at the end of the present substep
// (what contacts test against), with a moving one swept through the substep by intermediate
// poses when it moves farther than about half its size, so that cloth it overtakes is pushed
// ahead rather than jumped over (a sampled sweep: each pose in turn pushes the particle out).
// A sweep has at most kMaxSweep poses; one that needed more, with cloth in its way, is reported
// (outrun()), and the simulation stops there with an error rather than pass cloth silently.
#pragma once

#include <vector>

#include "drape/collider.h"
#include "drape/scene.h"

namespace drape {

class ColliderSet {
 public:
  ColliderSet() = default;
  /// Builds every collider (a mesh's BVH once) and poses them at time t.
  ColliderSet(const std::vector<ColliderDef>& defs, double t);

  /// Whether any collider moves, by its motion or the hand (else pose() does nothing).
  bool moves() const { return moves_; }
  /// Poses the colliders for the substep from t0 to t1 (s): contact() then holds each at t1,
  /// preceded by its intermediate poses where it sweeps, each knowing its motion since t0.
  void pose(double t0, double t1);
  /// Poses them at t, still (between frames: drawing, diagnostics, the next frame's start).
  /// Returns whether any is elsewhere than at the last settle (it did work on the cloth).
  bool settle(double t);

  /// The user's hand moves collider k (the viewer's Shift-drag): from where the hand last left
  /// it, it is carried `offset` (m) away from where its definition and motion put it, arriving
  /// linearly over [t0, t1] (the next frame), so its surface moves with the hand's velocity.
  /// A move farther than one substep's sweep covers (kMaxSweep poses) goes that far in each
  /// such span, each settle() at its end starting the next, until it arrives; t1 = t0 places
  /// it at once.
  void hand(size_t k, const Vec3& offset, double t0, double t1);
  /// Where the hand has put collider k (zero until it does).
  Vec3 hand_offset(size_t k) const { return hand_to_.empty() ? Vec3::Zero() : hand_goal_[k]; }

  /// How far (m) a point of collider k's surface moves at most between times t0 and t1.
  double travel(size_t k, double t0, double t1) const;

  /// How many substeps a frame from t0 to t1 (s) needs so that in each, every moving collider,
  /// and every still sphere and capsule, moves relative to the cloth near it by at most a
  /// sixteenth of its size across (a sphere's radius; an eighth of a sweep pose's step): its
  /// own travel plus the fastest move of a particle that can reach it, at the velocities v
  /// (the frame's start). One that no free particle can reach this frame does not count. For a
  /// method that steps a whole frame at once (`implicit`), where the sweep's poses alone push cloth
  /// out round a small fast body's sides one after another, cloth flung at a body that has just
  /// stopped jumps it, and a sheet falling fast onto a small still ball parts round it in one step
  /// (its particles each stopped at the tangent plane where they started) and lets it through. A
  /// still box or mesh does not count: its contacts take the side a particle came in by
  /// (entered_elsewhere), so one step does not cross it, however thin it is. The fraction is
  /// measured (the curtain's ball, README "Motion"): an eighth of the radius let the ball
  /// through, a tenth held; a sixteenth, for a margin. With Counted::still_round only the still
  /// spheres and capsules count (`auto`, whose xpbd keeps the cloth's triangles out of moving
  /// ones). At least 1, at most kMaxSubsteps.
  enum class Counted { all, still_round };
  int substeps_for(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                   const std::vector<double>& inv_mass, double t0, double t1,
                   Counted counted = Counted::all) const;
  static constexpr int kSubstepsPerPose = 8;
  static constexpr int kMaxSubsteps = 64;

  /// What contacts test against this substep (the sweep's poses included).
  const std::vector<Collider>& contact() const { return contact_; }
  /// One per definition, where it is now.
  const std::vector<Collider>& now() const { return now_; }
  int64_t bytes() const;

  /// The most poses one collider is swept through in a substep.
  static constexpr int kMaxSweep = 32;

  /// A collider that, in a substep since the last settle(), moved farther than its sweep's
  /// kMaxSweep poses can push cloth ahead, with cloth in its path: a triangle (its corners at x
  /// now, each having moved at most |v|·dt over the frame) meeting the box that bounds the
  /// collider's poses through that substep. Cloth it met there may have been passed through.
  /// collider is -1 when there is none (the first such collider otherwise).
  struct Outrun {
    int collider = -1;
    double travel = 0.0;   ///< m, its surface's move in the substep
    double covered = 0.0;  ///< m, the most its sweep's poses push cloth ahead (see most_step_)
  };
  Outrun outrun(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                const std::vector<Triangle>& triangles, double dt) const;

 private:
  Collider posed(size_t k, const Pose& pose, const Pose& start, double elapsed) const;
  /// Starts the hand's leg over [t0, t1] towards hand_goal_ from where each collider is at t0.
  void hand_leg(double t0, double t1);
  /// How far along its move from hand_from_ to hand_to_ the hand is at time t, in [0, 1].
  double hand_along(double t) const;
  /// Collider k's pose at time t: its motion's, carried by the hand.
  Pose pose_of(size_t k, double t) const;
  /// Whether collider k moves: it has a motion, or the hand has moved it.
  bool moving(size_t k) const { return defs_[k].motion.moves() || (!held_.empty() && held_[k]); }
  /// Records that collider k's sweep over a substep, from `start` through `poses` (its pieces'
  /// colliders), moved `moved` m, farther than its poses cover.
  void note_outrun(size_t k, const Pose& start, const Collider* poses, int pieces, double moved);
  /// travel() between two poses of collider k already found.
  double travel(size_t k, const Pose& start, const Pose& end) const;

  std::vector<ColliderDef> defs_;  ///< their motions (meshes shared with the rest colliders)
  std::vector<Collider> rest_;     ///< as defined, unmoved
  std::vector<Vec3> reference_;    ///< each one's point its motion turns about (see MotionDef)
  std::vector<double> size_;       ///< m, how far it may move in one pose of a sweep
  /// m, the longest step between two poses after which the second still pushes a particle the
  /// first left at its surface out ahead (not out its back): half its thickness across plus
  /// the contact thickness (more than size_).
  std::vector<double> most_step_;
  std::vector<Collider> now_, contact_;
  std::vector<Pose> settled_;  ///< each one's pose at the last settle
  /// Since the last settle: each collider's longest move in a substep its sweep did not cover
  /// (0: none), and the box bounding its poses in those substeps.
  std::vector<double> outran_;
  std::vector<Vec3> outran_lo_, outran_hi_;
  /// The hand's offsets (empty until it moves one): from, to, over [hand_t0_, hand_t1_], and
  /// where it put each (which the legs reach in turn).
  std::vector<Vec3> hand_from_, hand_to_, hand_goal_;
  std::vector<uint8_t> held_;  ///< 1 for each one the hand has moved
  double hand_t0_ = 0.0, hand_t1_ = 0.0;
  bool moves_ = false;
};

/// A collider's reference point: sphere and box centre, capsule's middle, plane's point, mesh's
/// transform translation.
Vec3 reference_point(const ColliderDef& def);

}  // namespace drape
