// Colliders of any shape and colliders that move: distances and normals against closed forms,
// a mesh shaped as a sphere against the analytic sphere, Coulomb friction on a tilted box, a
// turning sphere carrying cloth, a fast ball that pushes a curtain instead of passing through
// it, keyed motion against hand-computed poses, scene keys (bad input, write-back) and
// determinism with a moving collider.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "brute_force_crossings.h"
#include "collision/collider_set.h"
#include "collision/motion.h"
#include "collision/point_push.h"
#include "collision/triangle_contact.h"
#include "collision/triangle_shape.h"
#include "drape/collider.h"
#include "drape/error.h"
#include "drape/simulation.h"
#include "io/collider_mesh.h"
#include "io/scene_io.h"
#include "temp_dir.h"
#include "test_scenes.h"
#include "variants.h"

namespace drape {
namespace {

using nlohmann::json;
using testing_support::bare;
using testing_support::Variant;

constexpr double kDeg = std::numbers::pi / 180.0;

double distance(const Collider& c, const Vec3& x, Vec3* normal = nullptr) {
  Vec3 n;
  const double d = signed_distance(c, x, n);
  if (normal) *normal = n;
  return d;
}

// ---- Shapes against closed forms ------------------------------------------------------------

TEST(Capsule, DistanceAndNormalBesideTheAxisAndBeyondItsEnds) {
  ColliderDef def;
  def.type = ColliderType::capsule;
  def.a = Vec3(0.0, 0.0, 0.0);
  def.b = Vec3(2.0, 0.0, 0.0);
  def.radius = 0.5;
  const Collider c = make_collider(def);
  Vec3 n;
  EXPECT_NEAR(distance(c, Vec3(1.0, 2.0, 0.0), &n), 1.5, 1e-12);  // beside: to the axis
  EXPECT_TRUE(n.isApprox(Vec3::UnitY()));
  EXPECT_NEAR(distance(c, Vec3(1.0, 0.0, -0.2), &n), -0.3, 1e-12);  // inside
  EXPECT_TRUE(n.isApprox(-Vec3::UnitZ()));
  EXPECT_NEAR(distance(c, Vec3(5.0, 4.0, 0.0), &n), 5.0 - 0.5, 1e-12);  // beyond b: to b
  EXPECT_TRUE(n.isApprox(Vec3(3.0, 4.0, 0.0) / 5.0));
  EXPECT_NEAR(distance(c, Vec3(-1.0, 0.0, 0.0), &n), 0.5, 1e-12);  // beyond a, on the axis
  EXPECT_TRUE(n.isApprox(-Vec3::UnitX()));
}

TEST(Capsule, WithBothEndsAtOnePointIsASphere) {
  ColliderDef def;
  def.type = ColliderType::capsule;
  def.a = def.b = Vec3(1.0, 1.0, 1.0);
  def.radius = 0.25;
  const Collider c = make_collider(def);
  Vec3 n;
  EXPECT_NEAR(distance(c, Vec3(1.0, 2.0, 1.0), &n), 0.75, 1e-12);
  EXPECT_TRUE(n.isApprox(Vec3::UnitY()));
}

TEST(Box, RotatedDistanceToFacesEdgesAndCornersAndInside) {
  ColliderDef def;
  def.type = ColliderType::box;
  def.center = Vec3(1.0, 2.0, 3.0);
  def.half_extents = Vec3(1.0, 0.5, 0.25);
  def.rotate = Vec3(0.0, 0.0, 90.0);  // its x axis along world y, its y along world −x
  const Collider c = make_collider(def);
  const Mat3 R = c.rotation;
  EXPECT_TRUE((R * Vec3::UnitX()).isApprox(Vec3::UnitY()));
  auto world = [&](const Vec3& local) { return Vec3(def.center + R * local); };
  Vec3 n;
  // Beyond a face: the distance along its normal.
  EXPECT_NEAR(distance(c, world(Vec3(0.2, 0.9, 0.1)), &n), 0.4, 1e-12);
  EXPECT_TRUE(n.isApprox(R * Vec3::UnitY()));
  // Beyond an edge: to the edge, the normal from it.
  EXPECT_NEAR(distance(c, world(Vec3(1.3, 0.9, 0.0)), &n), std::hypot(0.3, 0.4), 1e-12);
  EXPECT_TRUE(n.isApprox(R * Vec3(0.6, 0.8, 0.0)));
  // Beyond a corner.
  EXPECT_NEAR(distance(c, world(Vec3(-2.0, -1.5, -1.25)), &n), std::sqrt(3.0), 1e-12);
  EXPECT_TRUE(n.isApprox(R * Vec3(-1.0, -1.0, -1.0) / std::sqrt(3.0)));
  // Inside: the nearest face, negative.
  EXPECT_NEAR(distance(c, world(Vec3(0.5, 0.0, 0.2)), &n), -0.05, 1e-12);
  EXPECT_TRUE(n.isApprox(R * Vec3::UnitZ()));
}

// A UV sphere as a closed mesh: its vertices on the sphere of `radius` around `centre`.
ClothMesh uv_sphere(const Vec3& centre, double radius, int segments, int rings) {
  Collider s;
  s.center = centre;
  s.radius = radius;
  const io::SurfaceMesh m = io::collider_mesh(s, Vec3::Zero(), 1.0, segments, rings);
  ClothMesh mesh;
  mesh.positions = m.position;
  for (const auto& t : m.triangles) mesh.triangles.push_back({t[0], t[1], t[2]});
  return mesh;
}

TEST(MeshShape, ClosedSphereGivesSignedDistancesAndOutwardNormals) {
  const ClothMesh m = uv_sphere(Vec3::Zero(), 1.0, 64, 32);
  const TriangleShape shape(m.positions, m.triangles);
  ASSERT_TRUE(shape.closed());
  // The chords lie inside the sphere by at most 1 − cos(π/32) (a ring's spacing).
  const double chord = 1.0 - std::cos(std::numbers::pi / 32);
  for (const Vec3& dir : {Vec3(1, 2, 3), Vec3(-1, 0.1, 0.3), Vec3(0.2, -1, -0.1), Vec3(0, 1, 0)}) {
    const Vec3 u = dir.normalized();
    for (const double r : {0.3, 0.9, 1.2, 2.5}) {
      Vec3 n;
      const double d = shape.signed_distance(r * u, n);
      EXPECT_NEAR(d, r - 1.0, chord + 1e-12) << r;
      EXPECT_GT(n.dot(u), 0.99) << r;  // outward, inside as well as outside
    }
  }
}

TEST(MeshShape, TurnedInsideOutStillHasItsInsideInside) {
  ClothMesh m = uv_sphere(Vec3::Zero(), 1.0, 16, 8);
  for (Triangle& t : m.triangles) std::swap(t[1], t[2]);
  const TriangleShape shape(m.positions, m.triangles);
  Vec3 n;
  EXPECT_LT(shape.signed_distance(Vec3(0.1, 0.2, 0.0), n), -0.5);
  EXPECT_GT(shape.signed_distance(Vec3(0.0, 3.0, 0.0), n), 1.9);
  EXPECT_GT(n.y(), 0.99);
}

TEST(MeshShape, AnOpenSheetIsTwoSided) {
  // A unit square in the x–z plane, two triangles.
  const std::vector<Vec3> v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 0, 1)};
  const TriangleShape shape(v, {{0, 2, 1}, {0, 3, 2}});
  EXPECT_FALSE(shape.closed());
  Vec3 n;
  EXPECT_NEAR(shape.signed_distance(Vec3(0.5, 0.3, 0.5), n), 0.3, 1e-12);
  EXPECT_TRUE(n.isApprox(Vec3::UnitY()));
  EXPECT_NEAR(shape.signed_distance(Vec3(0.5, -0.3, 0.5), n), 0.3, 1e-12);
  EXPECT_TRUE(n.isApprox(-Vec3::UnitY()));
  EXPECT_NEAR(shape.signed_distance(Vec3(2.0, 0.0, 0.5), n), 1.0, 1e-12);  // to the edge
  EXPECT_TRUE(n.isApprox(Vec3::UnitX()));
}

TEST(MeshShape, ABigMeshAnswersLikeAScanOfEveryTriangle) {
  // A fine sphere (about 32 000 triangles) against the closest point found by brute force.
  const ClothMesh m = uv_sphere(Vec3(0.1, 0.2, 0.3), 0.7, 256, 64);
  const TriangleShape shape(m.positions, m.triangles);
  ColliderDef def;
  def.type = ColliderType::mesh;
  def.mesh = std::make_shared<const ClothMesh>(m);
  const Collider c = make_collider(def);
  for (int k = 0; k < 50; ++k) {
    const Vec3 p(std::sin(1.3 * k), std::cos(0.7 * k) * 1.1, std::sin(0.37 * k + 1.0) * 0.9);
    double best = 1e300;
    for (const Triangle& t : shape.triangles()) {
      // Sample-free: the distance to the triangle's plane, edges and vertices.
      const Vec3 &a = shape.vertices()[t[0]], &b = shape.vertices()[t[1]],
                 &cc = shape.vertices()[t[2]];
      const Vec3 nrm = (b - a).cross(cc - a).normalized();
      const Vec3 q = p - nrm.dot(p - a) * nrm;
      const bool inside = (b - a).cross(q - a).dot(nrm) >= 0 &&
                          (cc - b).cross(q - b).dot(nrm) >= 0 &&
                          (a - cc).cross(q - cc).dot(nrm) >= 0;
      if (inside) best = std::min(best, (p - q).norm());
      for (const auto& [u, w] : {std::pair{a, b}, {b, cc}, {cc, a}}) {
        const double s = std::clamp((p - u).dot(w - u) / (w - u).squaredNorm(), 0.0, 1.0);
        best = std::min(best, (p - (u + s * (w - u))).norm());
      }
    }
    EXPECT_NEAR(std::abs(distance(c, p)), best, 1e-12) << k;
  }
}

// ---- Drawn shapes lie on their surfaces -----------------------------------------------------

TEST(ColliderMesh, CapsuleBoxAndMeshAreDrawnOnTheirSurfacesFacingOut) {
  std::vector<ColliderDef> defs(3);
  defs[0].type = ColliderType::capsule;
  defs[0].a = Vec3(0.0, 0.0, 0.0);
  defs[0].b = Vec3(1.0, 1.0, 0.0);
  defs[0].radius = 0.3;
  defs[1].type = ColliderType::box;
  defs[1].center = Vec3(0.0, 1.0, 0.0);
  defs[1].half_extents = Vec3(0.5, 0.2, 0.3);
  defs[1].rotate = Vec3(10.0, 20.0, 30.0);
  defs[2].type = ColliderType::mesh;
  defs[2].mesh = std::make_shared<const ClothMesh>(uv_sphere(Vec3::Zero(), 0.5, 16, 8));
  defs[2].transform.translate = Vec3(0.0, 2.0, 0.0);
  for (const ColliderDef& def : defs) {
    const Collider c = make_collider(def);
    const io::SurfaceMesh m = io::collider_mesh(c, Vec3::Zero(), 1.0);
    ASSERT_FALSE(m.triangles.empty()) << to_string(def.type);
    for (size_t k = 0; k < m.position.size(); ++k) {
      Vec3 n;
      EXPECT_NEAR(signed_distance(c, m.position[k], n), 0.0, 1e-9) << to_string(def.type);
    }
    for (const auto& t : m.triangles) {
      const Vec3 centre = (m.position[t[0]] + m.position[t[1]] + m.position[t[2]]) / 3.0;
      const Vec3 area =
          (m.position[t[1]] - m.position[t[0]]).cross(m.position[t[2]] - m.position[t[0]]);
      EXPECT_GT(area.norm(), 0.0) << to_string(def.type);
      Vec3 n;
      signed_distance(c, centre + 1e-3 * area.normalized(), n);
      EXPECT_GT(area.dot(n), 0.0) << to_string(def.type);  // counter-clockwise from outside
    }
  }
}

// ---- Motion ---------------------------------------------------------------------------------

TEST(Motion, TranslatesLinearlyTurnsBySlerpAndHoldsAfterTheLastKey) {
  MotionDef m;
  m.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {2.0, Vec3(1.0, 0.0, 0.0), Vec3(0.0, 90.0, 0.0)}};
  const Vec3 ref(0.0, 1.0, 0.0);
  // Halfway: half the translation, 45° about y (the slerp of 0° and 90°) about the reference.
  Pose p = pose_at(m, ref, 1.0);
  const Vec3 x(1.0, 1.0, 0.0);  // 1 m from the reference along x
  const double c = std::cos(45 * kDeg), s = std::sin(45 * kDeg);
  EXPECT_TRUE(p.apply(x).isApprox(Vec3(0.5 + c, 1.0, -s), 1e-12)) << p.apply(x).transpose();
  EXPECT_TRUE(p.apply(ref).isApprox(ref + Vec3(0.5, 0.0, 0.0), 1e-12));
  // Before the first key the first holds; after the last the last holds.
  EXPECT_TRUE(pose_at(m, ref, -1.0).apply(x).isApprox(x, 1e-12));
  p = pose_at(m, ref, 5.0);
  EXPECT_TRUE(p.apply(x).isApprox(Vec3(1.0, 1.0, -1.0), 1e-12)) << p.apply(x).transpose();
}

TEST(Motion, LoopsAndTurnsAboutAPivot) {
  MotionDef m;
  m.keys = {{1.0, Vec3::Zero(), Vec3::Zero()}, {3.0, Vec3(0.0, 2.0, 0.0), Vec3::Zero()}};
  m.loop = true;
  // t = 6.5 is 1.5 s into the third span (5 to 7): three quarters of the way.
  EXPECT_TRUE(pose_at(m, Vec3::Zero(), 6.5).translation.isApprox(Vec3(0.0, 1.5, 0.0), 1e-12));
  MotionDef turn;
  turn.keys = {{0.0, Vec3::Zero(), Vec3(0.0, 0.0, 90.0)}};
  turn.has_pivot = true;
  turn.pivot = Vec3(1.0, 0.0, 0.0);
  // 90° about z about (1, 0, 0): the origin goes to (1, −1, 0).
  EXPECT_TRUE(pose_at(turn, Vec3(5.0, 5.0, 5.0), 0.0)
                  .apply(Vec3::Zero())
                  .isApprox(Vec3(1.0, -1.0, 0.0), 1e-12));
}

TEST(Motion, AColliderIsPosedAtEachSubstepAndItsSurfaceVelocityIsTheMotions) {
  ColliderDef def;
  def.center = Vec3(0.0, 0.0, 0.0);
  def.radius = 0.1;
  def.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3(2.0, 0.0, 0.0), Vec3::Zero()}};
  ColliderSet set({def}, 0.0);
  set.pose(0.25, 0.5);
  const Collider& c = set.contact().back();
  EXPECT_TRUE(c.center.isApprox(Vec3(1.0, 0.0, 0.0), 1e-12));
  EXPECT_TRUE(c.surface_velocity(Vec3(1.1, 0.0, 0.0)).isApprox(Vec3(2.0, 0.0, 0.0), 1e-12));
  // 0.5 m in the substep, 0.05 m a pose of the sweep (half the radius): ten poses.
  EXPECT_EQ(set.contact().size(), 10u);
}

// A body turning about a far pivot sweeps an arc, longer than the chord between where it starts
// and ends: its travel is at least the arc, and its sweep's poses lie close enough that no point
// of its surface moves farther than a pose's step (half its thickness across) from one to the next.
TEST(Motion, ABodyTurningAboutAFarPivotIsSweptAlongItsArc) {
  const double degrees = 170.0, turn = degrees * std::numbers::pi / 180.0;
  ColliderDef ball;
  ball.radius = 0.1;
  ball.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3::Zero(), Vec3(0, 0, degrees)}};
  ball.motion.has_pivot = true;
  ball.motion.pivot = Vec3(1.0, 0.0, 0.0);
  // Its centre's arc is 170° of a circle of 1 m: 2.97 m, where the chord is 1.99.
  EXPECT_NEAR(ColliderSet({ball}, 0.0).travel(0, 0.0, 1.0), turn, 1e-9);
  ColliderDef box;
  box.type = ColliderType::box;
  box.half_extents = Vec3::Constant(0.5);
  box.motion = ball.motion;
  box.motion.pivot = Vec3(1.5, 0.0, 0.0);
  ColliderSet set({box}, 0.0);
  const double step = 0.25;  // half its smallest extent
  set.pose(0.0, 1.0);
  const std::vector<Collider>& poses = set.contact();
  ASSERT_GT(poses.size(), 1u);
  ASSERT_LT(poses.size(), size_t{ColliderSet::kMaxSweep});  // not cut short
  double farthest = 0.0;  // a corner's largest move between two poses in a row
  Collider before = make_collider(box);
  for (const Collider& pose : poses) {
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 local((corner & 1 ? 0.5 : -0.5), (corner & 2 ? 0.5 : -0.5),
                       (corner & 4 ? 0.5 : -0.5));
      const Vec3 a = before.center + before.rotation * local,
                 b = pose.center + pose.rotation * local;
      farthest = std::max(farthest, (b - a).norm());
    }
    before = pose;
  }
  EXPECT_LE(farthest, step * (1.0 + 1e-9)) << poses.size() << " poses";
  // Keyed a vast distance, it is reported as moving that far, not infinitely.
  ball.motion.keys.back().translate = Vec3(1e300, 0.0, 0.0);
  EXPECT_TRUE(std::isfinite(ColliderSet({ball}, 0.0).travel(0, 0.0, 1.0)));
}

// A method stepping a frame at once takes substeps so that a moving collider, or a still ball,
// moves relative to the cloth near it by at most a sixteenth of its radius in each: its own
// travel plus the fastest move of a particle that can reach it this frame (a pinned one, or one
// too far away to, does not count; a still box does not count at all; nor does a body no free
// particle can reach this frame).
TEST(Motion, SubstepsKeepABodysMoveRelativeToTheClothNearItWithinASixteenthOfItsRadius) {
  ColliderDef def;
  def.radius = 0.16;
  def.thickness = 0.01;
  def.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3(3.0, 0.0, 0.0), Vec3::Zero()}};
  ColliderSet set({def}, 0.0);
  const double dt = 1.0 / 60.0;
  std::vector<Vec3> x = {Vec3(10.0, 0.0, 0.0)}, v = {Vec3::Zero()};
  std::vector<double> inv_mass = {1.0};
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt), 1) << "the cloth 10 m away: out of reach";
  x.front() = Vec3(0.2, 0.0, 0.0);  // 2 cm beyond its thickness, still
  // 3 m/s: 5 cm a frame, 5 of the radius's sixteenths (1 cm).
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt), 5);
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt, ColliderSet::Counted::still_round), 1);
  // Another particle 4 cm beyond the surface coming at 3.6 m/s: 5 + 6 cm, 11 sixteenths.
  x.emplace_back(0.2, 0.0, 0.0);
  v.emplace_back(-3.6, 0.0, 0.0);
  inv_mass.push_back(1.0);
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt), 11);
  inv_mass.back() = 0.0;  // pinned: it goes where its pin says
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt), 5);
  inv_mass.back() = 1.0;
  x.back() = Vec3(0.4, 0.0, 0.0);  // 23 cm beyond the thickness: out of reach this frame
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 0.0, dt), 5);
  set.settle(1.0);                 // where it stops (the frame's start, as Simulation leaves it)
  x.back() = Vec3(3.2, 0.0, 0.0);  // at the stopped body, flung at it: 6 cm, 6 sixteenths
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 1.0, 1.0 + dt), 6);
  x.back() = Vec3(3.4, 0.0, 0.0);
  EXPECT_EQ(set.substeps_for(x, v, inv_mass, 1.0, 1.0 + dt), 1) << "nothing near it: still";
  def.motion.keys.clear();
  EXPECT_EQ(ColliderSet({def}, 0.0).substeps_for(x, v, inv_mass, 0.0, dt), 1) << "no motion";
  x.back() = Vec3(0.2, 0.0, 0.0);  // a still ball, the particle 4 cm out at 3.6 m/s: 6 cm
  EXPECT_EQ(ColliderSet({def}, 0.0).substeps_for(x, v, inv_mass, 0.0, dt), 6);
  EXPECT_EQ(ColliderSet({def}, 0.0)
                .substeps_for(x, v, inv_mass, 0.0, dt, ColliderSet::Counted::still_round),
            6);
  ColliderDef box = def;  // as wide, its face as near: a half-space the particle cannot cross
  box.type = ColliderType::box;
  box.half_extents = Vec3::Constant(0.16);
  EXPECT_EQ(ColliderSet({box}, 0.0).substeps_for(x, v, inv_mass, 0.0, dt), 1);
  // A body keyed to cross 1e12 m in a second: the most substeps, and the most poses of its
  // sweep (the counts once overflowed an int and came out as one).
  def.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3(1e12, 0.0, 0.0), Vec3::Zero()}};
  ColliderSet far({def}, 0.0);
  EXPECT_EQ(far.substeps_for(x, v, inv_mass, 0.0, dt), ColliderSet::kMaxSubsteps);
  far.pose(0.0, dt);
  EXPECT_EQ(far.contact().size(), size_t{ColliderSet::kMaxSweep});
  EXPECT_EQ(far.outrun({x[0], x[0], x[1]}, {v[0], v[0], v[1]}, {{0, 1, 2}}, dt).collider, 0)
      << "its poses jumped the cloth";
}

// A sweep whose poses lie farther apart than a pose can push a particle ahead (half the body's
// thickness across plus the contact thickness: a ball's radius + thickness) may have jumped the
// cloth: it is reported when a particle lies in the box its poses span, and only then.
TEST(Motion, ASweepWhosePosesJumpedIsReportedWhereClothLiesInItsPath) {
  ColliderDef def;
  def.radius = 0.1;
  def.thickness = 0.01;
  def.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()}, {1.0, Vec3(40.0, 0.0, 0.0), Vec3::Zero()}};
  ColliderSet set({def}, 0.0);
  // A cloth of one triangle, 2 cm across, about p.
  const std::vector<Triangle> cloth = {{0, 1, 2}};
  auto at = [](const Vec3& p) {
    return std::vector<Vec3>{p, p + Vec3(0.02, 0.0, 0.0), p + Vec3(0.0, 0.02, 0.0)};
  };
  const std::vector<Vec3> still(3, Vec3::Zero()), rising(3, Vec3(0.0, 3.0, 0.0));
  // 32 poses of 0.11 m cover 3.52 m: 3.2 m in a substep is swept whole.
  set.pose(0.0, 0.08);
  EXPECT_EQ(set.outrun(at(Vec3(2.0, 0.0, 0.0)), still, cloth, 0.1).collider, -1);
  set.settle(0.08);
  set.pose(0.08, 0.18);  // from x = 3.2 to 7.2 m: 4 m
  const ColliderSet::Outrun out = set.outrun(at(Vec3(5.0, 0.0, 0.0)), still, cloth, 0.1);
  EXPECT_EQ(out.collider, 0);
  EXPECT_NEAR(out.travel, 4.0, 1e-9);
  EXPECT_NEAR(out.covered, 32 * 0.11, 1e-12);
  // The box spans its poses' centres grown by radius, thickness and a pose's step (0.235 m).
  EXPECT_EQ(set.outrun(at(Vec3(5.0, 0.5, 0.0)), still, cloth, 0.1).collider, -1)
      << "0.5 m beside its path";
  EXPECT_EQ(set.outrun(at(Vec3(5.0, 0.5, 0.0)), rising, cloth, 0.1).collider, 0)
      << "it came from within 0.3 m of the path this frame";
  EXPECT_EQ(set.outrun(at(Vec3(2.0, 0.0, 0.0)), still, cloth, 0.1).collider, -1)
      << "behind where the substep's sweep began";
  set.settle(0.18);
  EXPECT_EQ(set.outrun(at(Vec3(5.0, 0.0, 0.0)), still, cloth, 0.1).collider, -1)
      << "settle() starts the next frame";
}

// The viewer's Shift-drag: the hand carries a collider from where it is to the new offset over
// the next frame, so its surface moves at the hand's velocity, and it stays there after.
TEST(Motion, TheHandCarriesAColliderOverTheNextFrameAtTheHandsVelocity) {
  ColliderDef ball, ground;
  ball.radius = 0.1;
  ground.type = ColliderType::plane;
  ColliderSet set({ball, ground}, 1.0);
  EXPECT_FALSE(set.moves());
  set.hand(0, Vec3(0.3, 0.0, 0.0), 1.0, 1.1);
  EXPECT_TRUE(set.moves());
  set.pose(1.0, 1.05);
  // The ball swept through 3 poses 5 cm apart (half its radius), then the ground.
  ASSERT_EQ(set.contact().size(), 4u);
  const Collider& c = set.contact()[2];
  EXPECT_TRUE(c.center.isApprox(Vec3(0.15, 0.0, 0.0), 1e-12));
  EXPECT_TRUE(c.surface_velocity(Vec3(0.25, 0.0, 0.0)).isApprox(Vec3(3.0, 0.0, 0.0), 1e-12));
  EXPECT_FALSE(set.contact().back().moving) << "the ground the hand did not move stands still";
  set.settle(1.1);
  EXPECT_TRUE(set.now().front().center.isApprox(Vec3(0.3, 0.0, 0.0), 1e-12));
  set.pose(1.1, 1.15);
  EXPECT_TRUE(set.contact().front().surface_velocity(Vec3::Zero()).isZero()) << "at rest after";
  EXPECT_TRUE(set.contact().front().center.isApprox(Vec3(0.3, 0.0, 0.0), 1e-12));
  // A new offset starts from where the last one was cut short.
  set.hand(0, Vec3(0.0, 0.2, 0.0), 1.15, 1.25);
  set.hand(0, Vec3(0.0, 0.4, 0.0), 1.2, 1.3);
  set.settle(1.2);
  EXPECT_TRUE(set.now().front().center.isApprox(Vec3(0.15, 0.1, 0.0), 1e-12));
  set.settle(1.3);
  EXPECT_TRUE(set.now().front().center.isApprox(Vec3(0.0, 0.4, 0.0), 1e-12));
}

// A fling farther than one substep's sweep covers (32 poses of half the ball's radius, 1.6 m)
// is carried that far a frame, each frame's settle starting the next leg, until the ball is
// where the hand put it: its poses never jump. Placing it with no time (a panel change) is
// at once.
TEST(Motion, TheHandCarriesAFlungColliderAtMostOneSweepAFrame) {
  ColliderDef ball;
  ball.radius = 0.1;
  ColliderSet set({ball}, 1.0);
  set.hand(0, Vec3(5.0, 0.0, 0.0), 1.0, 1.1);
  EXPECT_TRUE(set.hand_offset(0).isApprox(Vec3(5.0, 0.0, 0.0))) << "where the hand put it";
  const std::vector<Vec3> x(3, Vec3(2.5, 0.0, 0.0)), v(3, Vec3::Zero());
  for (int frame = 1; frame <= 4; ++frame) {
    const double t0 = 1.0 + 0.1 * (frame - 1);
    set.pose(t0, t0 + 0.1);
    EXPECT_EQ(set.outrun(x, v, {{0, 1, 2}}, 0.1).collider, -1);
    set.settle(t0 + 0.1);
    EXPECT_NEAR(set.now().front().center.x(), std::min(1.6 * frame, 5.0), 1e-12);
  }
  set.pose(1.4, 1.5);
  EXPECT_TRUE(set.contact().front().surface_velocity(Vec3::Zero()).isZero()) << "arrived";
  ColliderSet placed({ball}, 1.0);
  placed.hand(0, Vec3(5.0, 0.0, 0.0), 1.0, 1.0);
  placed.settle(1.0);
  EXPECT_TRUE(placed.now().front().center.isApprox(Vec3(5.0, 0.0, 0.0)));
}

// ---- Scene keys -----------------------------------------------------------------------------

std::string error_of(const json& j, const std::string& folder = "") {
  try {
    io::parse_scene(j, "test.json", folder);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A triangle slicing 5 mm into a ball that moves at 1 m/s along +z, its three corners outside
// the ball, coming at it with an inward and a sideways velocity relative to the surface: the
// push puts its point nearest the centre on the surface, stops the point's inward velocity and
// takes friction × that change off its slide (Coulomb), or all of the slide when friction is
// large (the point then moves with the surface).
TEST(TriangleContact, PushesATriangleOutOfAMovingBallAndHoldsItsSlideByFriction) {
  Collider ball;
  ball.radius = 0.1;
  ball.bound_radius = 0.1;
  ball.moving = true;
  ball.move_time = 0.01;
  ball.back_from = ball.center;
  ball.back_to = ball.center - Vec3(0.0, 0.0, 0.01);  // it came 1 cm in the last 0.01 s
  for (const double friction : {0.0, 0.5, 10.0}) {
    ball.friction = friction;
    ClothState state;
    state.x = {Vec3(-0.2, -0.1, 0.095), Vec3(0.2, -0.1, 0.095), Vec3(0.0, 0.2, 0.095)};
    state.v.assign(3, Vec3(0.5, 0.0, 0.8));  // relative to the surface: 0.5 aside, 0.2 inward
    state.inv_mass = {1.0, 2.0, 1.0};
    PointPush push;
    ASSERT_TRUE(triangle_push(ball, state.x[0], state.x[1], state.x[2], push));
    EXPECT_NEAR(push.depth, 0.005, 1e-12);
    EXPECT_NEAR((push.n - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    for (int k = 0; k < 3; ++k) push.index[k] = k;
    StateCloth cloth{state};
    cloth.push(push, ball);
    Vec3 point = Vec3::Zero(), v = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      point += push.w[k] * state.x[k];
      v += push.w[k] * state.v[k];
    }
    EXPECT_NEAR(point.norm(), ball.radius, 1e-12) << "friction " << friction;
    const Vec3 rel = v - Vec3(0.0, 0.0, 1.0);
    EXPECT_NEAR(rel.z(), 0.0, 1e-12) << "friction " << friction;
    EXPECT_NEAR(rel.x(), std::max(0.5 - friction * 0.2, 0.0), 1e-12) << "friction " << friction;
    EXPECT_NEAR(rel.y(), 0.0, 1e-12);
  }
  // A triangle wholly outside the ball is left alone.
  PointPush push;
  EXPECT_FALSE(triangle_push(ball, Vec3(-0.2, -0.1, 0.11), Vec3(0.2, -0.1, 0.11),
                             Vec3(0.0, 0.2, 0.11), push));
}

TEST(ColliderKeys, BadInputIsRefusedNamingTheKey) {
  const json box = {{"type", "box"}, {"center", {0, 0, 0}}, {"half_extents", {1, 1, 1}}};
  auto with = [](json c, const std::string& key, const json& value) {
    c[key] = value;
    return json{{"colliders", {c}}};
  };
  struct Case {
    json scene;
    std::string expected;
  };
  const json moving_keys = {{"keys", {{{"t", 1.0}}, {{"t", 1.0}}}}};
  const Case cases[] = {
      {json{{"colliders", {{{"type", "capsul"}}}}},
       "colliders[0].type: unknown value \"capsul\"; did you mean \"capsule\"?"},
      {json{{"colliders", {{{"type", "mesh"}, {"file", "no/such.obj"}}}}},
       "colliders[0].file (no/such.obj)"},
      {json{{"colliders", {{{"type", "mesh"}}}}}, "colliders[0].file: missing"},
      {with({{"type", "capsule"}}, "radius", -1.0), "colliders[0].radius"},
      {with(box, "half_extents", {1.0, -0.5, 1.0}), "colliders[0].half_extents[1]"},
      {with(box, "motion", moving_keys), "colliders[0].motion.keys[1].t: is 1, not after"},
      {with(box, "motion", json{{"keys", json::array()}}), "colliders[0].motion.keys"},
      {with(box, "rotate", {0, 0, "x"}), "colliders[0].rotate[2]"},
      {with(box, "motion", json{{"keys", {{{"t", 0.0}, {"spin", 1}}}}}),
       "colliders[0].motion.keys[0].spin: unknown key"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.scene);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << message << "\nexpected: " << c.expected;
  }
  // Non-finite values cannot be written in JSON; a definition made in C++ is checked the same.
  SceneDef def;
  ColliderDef b;
  b.type = ColliderType::box;
  b.center = Vec3(0.0, std::nan(""), 0.0);
  def.colliders = {b};
  EXPECT_THROW(check(def), InputError);
  def.colliders[0].center = Vec3::Zero();
  def.colliders[0].motion.keys = {
      {0.0, Vec3(std::numeric_limits<double>::infinity(), 0, 0), Vec3::Zero()}};
  try {
    check(def);
    ADD_FAILURE() << "an infinite translation was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "colliders[0].motion.keys[0].translate");
  }
}

TEST(ColliderKeys, AClothStartingInsideABoxIsNamed) {
  SceneDef def = bare();
  ColliderDef b;
  b.type = ColliderType::box;
  b.center = Vec3(0.0, 1.5, 0.0);  // the default cloth hangs from y = 2 to 0 at z = 0
  b.half_extents = Vec3(0.3, 0.3, 0.3);
  def.colliders = {b};
  try {
    Simulation sim(def);
    ADD_FAILURE() << "a cloth inside a box was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "colliders[0]");
    EXPECT_NE(std::string(e.what()).find("inside this box"), std::string::npos) << e.what();
  }
}

class ColliderFiles : public testing_support::TempDirTest {
 protected:
  ColliderFiles() : TempDirTest("drape_colliders_") {}
};

TEST_F(ColliderFiles, EveryNewKeyRoundTripsThroughTheWriter) {
  const std::string obj = path("ball.obj");
  {
    const ClothMesh m = uv_sphere(Vec3::Zero(), 0.3, 8, 4);
    std::ofstream out(obj);
    for (const Vec3& v : m.positions) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const Triangle& t : m.triangles)
      out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  }
  const json scene = {
      {"colliders",
       {{{"type", "capsule"},
         {"a", {0, 0, -1}},
         {"b", {0, 0, 1}},
         {"radius", 0.2},
         {"motion",
          {{"keys", {{{"t", 0}, {"translate", {0, 0, 0}}}, {{"t", 1}, {"rotate", {0, 90, 0}}}}},
           {"loop", true},
           {"pivot", {1, 2, 3}}}}},
        {{"type", "box"},
         {"center", {0, -1, 0}},
         {"half_extents", {1, 0.5, 1}},
         {"rotate", {0, 0, 10}}},
        {{"type", "mesh"},
         {"file", "ball.obj"},
         {"transform", {{"translate", {0, -2, 0}}, {"scale", 2}}}}}}};
  const SceneDef a = io::parse_scene(scene, "test.json", dir_.string());
  ASSERT_EQ(a.colliders.size(), 3u);
  EXPECT_EQ(a.colliders[2].mesh->positions.size(),
            uv_sphere(Vec3::Zero(), 0.3, 8, 4).positions.size());
  const json ja = io::to_json(a);
  EXPECT_EQ(io::to_json(io::parse_scene(ja, "again.json")), ja);
  EXPECT_TRUE(a.colliders[0].motion.loop);
  EXPECT_EQ(a.colliders[0].motion.pivot, Vec3(1, 2, 3));
}

// ---- Whole simulations ----------------------------------------------------------------------

class EveryMethod : public ::testing::TestWithParam<Variant> {};

// A 0.5 m sphere, once analytic and once as a closed mesh of about 65 000 triangles: a cloth
// draped over each comes to the same rest shape within 1 cm.
TEST_P(EveryMethod, AMeshSphereDrapesLikeTheAnalyticSphere) {
  SceneDef def = testing_support::with(bare(), GetParam());
  // A strip 1 m long laid across the top: it bends over the sphere along a great circle with
  // nothing to buckle, so its rest shape is one (an analytic sphere 100 µm larger or smaller
  // moves it at most 0.7 mm with every method, measured). A 1 m square's rim wrinkles instead:
  // an analytic sphere 100 µm larger, about the mesh's facets' depth, moved implicit's rest
  // shape 8.2 mm, so the test compared wrinkles more than colliders.
  def.cloth.cols = 16;
  def.cloth.rows = 3;
  def.cloth.width = 1.0;
  def.cloth.height = 0.12;
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.origin = Vec3(-0.5, 0.55, -0.06);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.forces.air_drag = 0.01;
  ColliderDef sphere;
  sphere.radius = 0.5;
  sphere.friction = 0.5;
  def.colliders = {sphere};
  SceneDef mesh_def = def;
  ColliderDef mesh = sphere;
  mesh.type = ColliderType::mesh;
  mesh.mesh = std::make_shared<const ClothMesh>(uv_sphere(Vec3::Zero(), 0.5, 256, 128));
  mesh_def.colliders = {mesh};
  Simulation a(def), b(mesh_def);
  for (int f = 0; f < 180; ++f) {
    ASSERT_TRUE(a.step()) << a.divergence();
    ASSERT_TRUE(b.step()) << b.divergence();
  }
  double worst = 0.0;
  for (int32_t i = 0; i < a.model().size(); ++i)
    worst = std::max(worst, (a.state().x[i] - b.state().x[i]).norm());
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(b.diagnostics().max_penetration, 0.01);
}

// A patch on a box tilted by θ, friction μ: at rest while tan θ < μ; sliding with the
// acceleration g(sin θ − μ cos θ) while tan θ > μ (Coulomb; the patch moves as one body).
TEST_P(EveryMethod, CoulombFrictionHoldsOrSlidesAPatchOnATiltedBox) {
  const double mu = 0.5;
  for (const double degrees : {20.0, 35.0}) {
    const double theta = degrees * kDeg;
    SceneDef def = testing_support::with(bare(), GetParam());
    def.forces.gravity = Vec3(0.0, -9.81, 0.0);
    ClothMesh patch = shapes::jittered_grid(0.3, 7, 0.0);
    def.cloth.mesh = std::make_shared<const ClothMesh>(patch);
    def.cloth.cols = def.cloth.rows = ClothDef{}.cols;  // the grid's keys at their defaults
    def.cloth.transform.rotate = Vec3(0.0, 0.0, degrees);
    // The thickness above the face, along its normal (closer, a position-based method would
    // turn the depth it removes in the first substep into a velocity).
    def.cloth.transform.translate = rotation_xyz(Vec3(0.0, 0.0, degrees)) * Vec3(0.0, 0.01, 0.0);
    def.cloth.mass = 0.05;
    ColliderDef box;
    box.type = ColliderType::box;
    box.half_extents = Vec3(1.5, 0.5, 1.5);
    box.rotate = Vec3(0.0, 0.0, degrees);
    box.center = rotation_xyz(box.rotate) * Vec3(0.0, -0.5, 0.0);  // top face through 0
    box.friction = mu;
    def.colliders = {box};
    Simulation sim(def);
    auto centre = [&] {
      Vec3 c = Vec3::Zero();
      for (const Vec3& x : sim.state().x) c += x;
      return Vec3(c / sim.model().size());
    };
    const Vec3 start = centre();
    const double t = 0.5;
    while (sim.time() < t - 1e-9) ASSERT_TRUE(sim.step()) << sim.divergence();
    const Vec3 down_slope = Vec3(-std::cos(theta), -std::sin(theta), 0.0);
    const double moved = (centre() - start).dot(down_slope);
    if (std::tan(theta) < mu) {
      EXPECT_LT(std::abs(moved), 0.005) << degrees;
    } else {
      const double expected = 0.5 * 9.81 * (std::sin(theta) - mu * std::cos(theta)) * t * t;
      EXPECT_NEAR(moved, expected, 0.25 * expected) << degrees;
    }
  }
}

// An 8×8 patch of 0.3 m and 50 g lying on top of a still 0.5 m ball with friction 1.
SceneDef patch_on_a_ball(const Variant& variant) {
  SceneDef def = testing_support::with(bare(), variant);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.cloth.width = def.cloth.height = 0.3;
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.origin = Vec3(-0.15, 0.52, -0.15);
  def.cloth.mass = 0.05;
  ColliderDef ball;
  ball.radius = 0.5;
  ball.friction = 1.0;
  def.colliders = {ball};
  return def;
}

// A patch resting on top of a sphere that turns about the vertical at 90°/s is carried round
// by friction: a corner turns about the axis with the sphere.
TEST_P(EveryMethod, ATurningSphereCarriesTheClothOnIt) {
  SceneDef def = patch_on_a_ball(GetParam());
  // fast damps each spring's whole relative velocity (fast.cpp), a rigid turn's included: with
  // the springs' default damping it brakes the patch more than friction turns it (3° in the
  // second, measured), so friction is tested here without it.
  if (GetParam().method == Method::fast)
    def.cloth.structural.damping = def.cloth.shear.damping = def.cloth.bending.damping = 0.0;
  ColliderDef& sphere = def.colliders.front();
  // Keys a third of a turn apart (a slerp turns the short way), looping every 4 s.
  for (int k = 0; k <= 3; ++k)
    sphere.motion.keys.push_back({4.0 * k / 3.0, Vec3::Zero(), Vec3(0.0, 120.0 * k, 0.0)});
  sphere.motion.loop = true;
  Simulation sim(def);
  const int32_t corner = sim.model().index(def.cloth.cols - 1, 0);
  auto angle = [&] {
    const Vec3& x = sim.state().x[corner];
    return std::atan2(-x.z(), x.x());  // about +y, counter-clockwise seen from above
  };
  const double start = angle();
  while (sim.time() < 1.0 - 1e-9) ASSERT_TRUE(sim.step()) << sim.divergence();
  // The sphere turned 90°; the patch, settling onto it first and brought up to speed by a
  // friction of at most μ·g, turns at most as far. implicit at one substep a frame lags: it
  // reaches about 59° (83° at 4 substeps). Its large step brakes the turning of the patch,
  // stretched over the ball (each step's solve takes angular momentum about the axis out, as
  // much as friction puts in: measured), by about h²·ω·tension per spring, so less with
  // substeps; with μ = 2 or more it reaches 73°.
  double turned = angle() - start;
  if (turned < -std::numbers::pi) turned += 2.0 * std::numbers::pi;
  EXPECT_GT(turned, 50.0 * kDeg);
  EXPECT_LT(turned, 92.0 * kDeg);
}

// How the shipped curtain's ball stands at frame f's end: the path its centre has swept since
// the start crosses `crossings` of the cloth's triangles, and the deepest particle lies `inside`
// m within its radius. Read from the scene's keys (0.5 s still, then 2 m in +z over 0.2 s), not
// from the library's colliders.
struct BallAgainstCurtain {
  int64_t crossings = 0;
  double inside = 0.0;
};
BallAgainstCurtain ball_against_curtain(const SceneDef& def, const Simulation& sim) {
  const ColliderDef& ball = def.colliders.at(0);
  const Vec3 start = ball.center;
  const Vec3 now = start + std::clamp((sim.time() - 0.5) / 0.2, 0.0, 1.0) * Vec3(0.0, 0.0, 2.0);
  BallAgainstCurtain out;
  const std::vector<Vec3>& x = sim.state().x;
  for (const Triangle& t : sim.model().triangles)
    out.crossings += testing_support::crosses(start, now, x[t[0]], x[t[1]], x[t[2]]);
  for (const Vec3& p : x) out.inside = std::max(out.inside, ball.radius - (p - now).norm());
  return out;
}

// The shipped curtain: a ball of radius 0.1 m at 10 m/s hits a curtain hanging from its top
// edge. The curtain gives way (pushed, it swings up and lets the ball pass under its hem), and
// at no frame's end has the ball's path gone through the cloth or a particle stayed inside the
// ball. Without contacts the same check sees the ball go straight through (it can fail).
TEST_P(EveryMethod, AFastBallPushesTheCurtainAsideAndNeverTunnelsThroughIt) {
  if (GetParam().line_passes > 0)
    GTEST_SKIP() << "line passes on a pinned cloth need cloth.long_range, whose taut curtain "
                    "cannot give way (README, Known traps)";
  SceneDef def = testing_support::with(testing_support::shipped("curtain"), GetParam());
  def.duration = 1.0;
  {
    SceneDef ghost = def;  // a ball the cloth does not feel: none
    ghost.colliders.clear();
    Simulation sim(ghost);
    while (sim.time() < 0.8) ASSERT_TRUE(sim.step()) << sim.divergence();
    EXPECT_GT(ball_against_curtain(def, sim).crossings, 0) << "the check sees no tunnelling";
  }
  Simulation sim(def);
  for (int64_t f = 0; f < frame_count(def); ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    const BallAgainstCurtain b = ball_against_curtain(def, sim);
    ASSERT_EQ(b.crossings, 0) << "the ball went through the curtain by frame " << f;
    ASSERT_LT(b.inside, 1e-3) << "a particle inside the ball at frame " << f;
  }
}

// A thin plate flung through the shipped curtain faster than its sweep's poses can push cloth
// ahead (2 m in 0.5 ms, at `fast`'s one substep a frame: 32 poses 6 cm apart, where one pushes
// a particle the pose before left at its face ahead only up to 1.5 cm, half its 1 cm across
// plus its thickness): the run stops at that frame with an error naming the collider, rather
// than let it pass the cloth without a word (without the check the plate ends 1 m beyond the
// curtain, the cloth in its footprint within 1.3 cm of where it hung). The same plate flung beside
// the curtain runs on.
TEST(Motion, APlateOutrunningItsSweepThroughTheCurtainStopsTheRunNamingIt) {
  SceneDef def = testing_support::shipped("curtain");
  def.solver.method = Method::fast;
  def.duration = 0.6;
  ColliderDef& plate = def.colliders.front();
  plate.type = ColliderType::box;
  plate.half_extents = Vec3(0.3, 0.3, 0.005);
  plate.motion.keys.back().t = 0.5005;
  {
    Simulation sim(def);
    while (sim.step()) ASSERT_LT(sim.frame(), frame_count(def)) << "it ran through";
    EXPECT_EQ(sim.diverged_frame(), 31) << sim.divergence();
    EXPECT_NE(sim.divergence().find("colliders[0] moved 2 m in one substep"), std::string::npos)
        << sim.divergence();
  }
  plate.center.x() += 3.0;
  Simulation beside(def);
  for (int64_t f = 0; f < frame_count(def); ++f) ASSERT_TRUE(beside.step()) << beside.divergence();
}

// Cloth moving fast at a small body that stands still: the seed's sphere scene without air,
// the ball 20 cm across, the sheet dropped from 5.2 m so it meets the ball at 10 m/s (17 cm a
// frame, three cells). At every frame's end the cloth covers the ball (the segment from its
// centre straight up crosses a cloth triangle; the sheet wraps round it and its hems may close
// below) and no particle is inside it; without contacts the same check sees the sheet fall
// through.
TEST_P(EveryMethod, ASheetFallingFastOntoASmallStillBallNeverTunnelsThroughIt) {
  SceneDef def = testing_support::with(testing_support::shipped("sphere"), GetParam());
  def.forces.air_drag = 0.0;
  def.cloth.origin.y() = 5.2;
  def.colliders.front().radius = 0.1;
  def.duration = 1.4;
  auto crossings_above = [](const SceneDef& d, const Simulation& sim) {
    const Vec3 c = d.colliders.front().center, above = c + Vec3(0.0, 20.0, 0.0);
    const std::vector<Vec3>& x = sim.state().x;
    int64_t n = 0;
    for (const Triangle& t : sim.model().triangles)
      n += testing_support::crosses(c, above, x[t[0]], x[t[1]], x[t[2]]);
    return n;
  };
  {
    SceneDef ghost = def;
    ghost.colliders.front().thickness = 0.0;
    ghost.colliders.front().radius = 1e-6;
    Simulation sim(ghost);
    while (sim.time() < 1.2) ASSERT_TRUE(sim.step()) << sim.divergence();
    EXPECT_EQ(crossings_above(def, sim), 0) << "the check sees nothing";
  }
  Simulation sim(def);
  const ColliderDef& ball = def.colliders.front();
  for (int64_t f = 0; f < frame_count(def); ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    ASSERT_GT(crossings_above(def, sim), 0) << "the sheet fell through the ball by frame " << f;
    double inside = 0.0;
    for (const Vec3& p : sim.state().x)
      inside = std::max(inside, ball.radius - (p - ball.center).norm());
    ASSERT_LT(inside, 1e-3) << "a particle inside the ball at frame " << f;
  }
}

// Cloth moving fast at a thin still body: the seed's sphere scene without air, its ball made a
// plate 1 cm thick and 1.2 m square (a box, and the same as a closed mesh), or a sheet of two
// triangles (an open mesh), the cloth dropped from 5.2 m so it meets the plate at 10 m/s (4 cm a
// substep at 4 substeps a frame, where the plate and its contact thickness span 3 cm). At every
// frame's end the middle of the cloth (its particles that started within 0.4 m of the plate's
// axis) lies above the plate, and no edge of the cloth passes through the plate farther than
// 10 cm inside its rim (its mid-plane crossed inside |x|, |z| < 0.5 m; at the rim the cloth
// wraps round it). Until the contacts took the side a particle came in by (entered_elsewhere),
// one that had crossed more than half the plate was pushed out of its far face: `auto` let the
// middle through the box and the closed mesh at frame 61 (144 particles), `fast` too (129, and
// 258 edges through), and `auto` had 3 edges through the open sheet at frame 75. Not reached, so
// not asked here: nearer the rim `auto`'s cloth is cut by the plate's corners (10 edges through
// within 5 to 10 cm of them, at frame 69; README, Colliders). Without the plate the same check
// sees the cloth fall through.
TEST_P(EveryMethod, ASheetFallingFastOntoAThinStillPlateNeverPassesThroughIt) {
  SceneDef def = testing_support::with(testing_support::shipped("sphere"), GetParam());
  def.forces.air_drag = 0.0;
  def.cloth.origin.y() = 5.2;
  def.duration = 1.3;
  const std::vector<Triangle> triangles = Simulation(def).model().triangles;
  // Every edge once, from the triangles.
  std::vector<std::array<int32_t, 2>> edges;
  for (const Triangle& t : triangles)
    for (int k = 0; k < 3; ++k)
      edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  auto through = [&](const std::vector<Vec3>& x) {
    int64_t n = 0;
    for (const auto& [i, j] : edges) {
      const Vec3 &a = x[i], &b = x[j];
      if (!(a.y() * b.y() < 0.0)) continue;
      const Vec3 p = a + (a.y() / (a.y() - b.y())) * (b - a);
      n += std::abs(p.x()) < 0.5 && std::abs(p.z()) < 0.5;
    }
    return n;
  };
  auto middle_below = [](const std::vector<Vec3>& start, const std::vector<Vec3>& x) {
    int64_t n = 0;
    for (size_t i = 0; i < x.size(); ++i)
      n += std::abs(start[i].x()) < 0.4 && std::abs(start[i].z()) < 0.4 && x[i].y() < 0.0;
    return n;
  };
  // The plates, centred on the origin.
  const double a = 0.6, h = 0.005;
  ColliderDef box = def.colliders.front();
  box.type = ColliderType::box;
  box.center = Vec3::Zero();
  box.half_extents = Vec3(a, h, a);
  auto mesh_plate = [&](std::vector<Vec3> corners, std::vector<Triangle> faces) {
    ColliderDef c = box;
    c.type = ColliderType::mesh;
    auto mesh = std::make_shared<ClothMesh>();
    mesh->positions = std::move(corners);
    mesh->triangles = std::move(faces);
    c.mesh = mesh;
    return c;
  };
  std::vector<Vec3> corners;
  for (const double y : {-h, h})
    for (const double x : {-a, a})
      for (const double z : {-a, a}) corners.emplace_back(x, y, z);
  // Corner (x, y, z) is 4·(y > 0) + 2·(x > 0) + (z > 0); each face's quads wound outward.
  const std::vector<Triangle> closed = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                        {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                        {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const std::vector<Vec3> sheet = {{-a, 0, -a}, {a, 0, -a}, {-a, 0, a}, {a, 0, a}};
  const std::pair<const char*, ColliderDef> plates[] = {
      {"box", box},
      {"closed mesh", mesh_plate(corners, closed)},
      {"open mesh", mesh_plate(sheet, {{0, 2, 3}, {0, 3, 1}})}};
  {
    SceneDef ghost = def;
    ghost.colliders.front().center.x() += 100.0;
    Simulation sim(ghost);
    const std::vector<Vec3> start = sim.state().x;
    int64_t below = 0;
    for (int64_t f = 0; f < frame_count(ghost); ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      below = std::max(below, middle_below(start, sim.state().x));
    }
    EXPECT_GT(below, 0) << "the check sees nothing";
  }
  for (const auto& [name, plate] : plates) {
    SCOPED_TRACE(name);
    def.colliders = {plate};
    Simulation sim(def);
    const std::vector<Vec3> start = sim.state().x;
    for (int64_t f = 0; f < frame_count(def); ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      ASSERT_EQ(middle_below(start, sim.state().x), 0) << "through the plate by frame " << f;
      ASSERT_EQ(through(sim.state().x), 0) << "edges through the plate at frame " << f;
    }
  }
}

// A box's corners from its definition (centre, half extents, rotation), not from the
// library's collider: bit 1, 2, 4 of k for +x, +y, +z.
std::array<Vec3, 8> box_corners(const ColliderDef& box) {
  const Mat3 r = rotation_xyz(box.rotate);
  std::array<Vec3, 8> corners;
  for (int k = 0; k < 8; ++k) {
    const Vec3 s((k & 1) ? 1.0 : -1.0, (k & 2) ? 1.0 : -1.0, (k & 4) ? 1.0 : -1.0);
    corners[k] = box.center + r * s.cwiseProduct(box.half_extents);
  }
  return corners;
}

// The same box as a closed mesh collider: two triangles per face.
ColliderDef box_as_mesh(const ColliderDef& box) {
  ColliderDef mesh = box;
  mesh.type = ColliderType::mesh;
  ClothMesh m;
  for (const Vec3& c : box_corners(box)) m.positions.push_back(c);
  for (const auto& f : {std::array{0, 4, 6, 2}, std::array{1, 3, 7, 5}, std::array{0, 1, 5, 4},
                        std::array{2, 6, 7, 3}, std::array{0, 2, 3, 1}, std::array{4, 5, 7, 6}}) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  mesh.mesh = std::make_shared<const ClothMesh>(m);
  return mesh;
}

// An open mesh collider 5 mm thick: the square of half side `half` in the x–z plane as two
// triangles, turned by `turn` about the origin.
ColliderDef square_sheet(double half, const Mat3& turn, double friction) {
  ClothMesh top;
  for (const Vec3& corner : {Vec3(-half, 0.0, -half), Vec3(half, 0.0, -half), Vec3(half, 0.0, half),
                             Vec3(-half, 0.0, half)})
    top.positions.push_back(turn * corner);
  top.triangles = {{0, 2, 1}, {0, 3, 2}};
  ColliderDef sheet;
  sheet.type = ColliderType::mesh;
  sheet.mesh = std::make_shared<const ClothMesh>(top);
  sheet.friction = friction;
  sheet.thickness = 0.005;
  return sheet;
}

// How many (segment, cloth triangle) pairs cross (the tests' own segment–triangle test).
int64_t segments_through_cloth(const std::vector<std::pair<Vec3, Vec3>>& segments,
                               const Simulation& sim) {
  const std::vector<Vec3>& x = sim.state().x;
  int64_t crossings = 0;
  for (const auto& [a, b] : segments)
    for (const Triangle& t : sim.model().triangles)
      crossings += testing_support::crosses(a, b, x[t[0]], x[t[1]], x[t[2]]);
  return crossings;
}

// A coarse 0.6 m cloth of 0.1 kg (5 cm cells) held flat at height y under gravity and a little
// drag: a 12 × 12 grid, or as_mesh an irregular mesh (the mesh solvers' contact paths).
SceneDef coarse_cloth_at(double y, bool as_mesh, const testing_support::Variant& variant) {
  SceneDef def = testing_support::with(bare(), variant);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.forces.air_drag = 0.01;
  if (as_mesh) {
    def.cloth.mesh = std::make_shared<const ClothMesh>(shapes::jittered_grid(0.6, 13));
    def.cloth.cols = def.cloth.rows = ClothDef{}.cols;  // the grid's keys at their defaults
    def.cloth.transform.translate = Vec3(0.0, y, 0.0);
  } else {
    def.cloth.cols = def.cloth.rows = 12;
    def.cloth.width = def.cloth.height = 0.6;
    def.cloth.orientation = Orientation::horizontal;
    def.cloth.origin = Vec3(-0.3, y, -0.3);
  }
  def.cloth.mass = 0.1;
  return def;
}

// A coarse cloth (5 cm cells) dropped over a small box standing on an edge-up or corner-up
// pose, as a box under a grid and as a closed mesh under an irregular mesh: the box's edges and
// corners meet the cloth between its particles, and no edge of the box may pass through a cloth
// triangle at any frame's end. Particle contacts alone let the cloth settle with the box poking
// through it (every method failed this by frame 26 before the feature contacts). The last two
// drops, slipperier, were found by varying the first ones: there a push across a corner the
// cloth lay beside wrapped it round the corner (`fast`, frame 55) or flung it through the box
// (`xpbd`, 28 cm in one frame, frame 48).
TEST_P(EveryMethod, ABoxsEdgesAndCornersNeverPierceTheCloth) {
  struct Drop {
    Vec3 rotate;
    bool as_mesh;
    double height = 0.35, friction = 0.5;
    Vec3 center = Vec3(0.01, 0.0, 0.02);
  };
  const Vec3 edge_up(0.0, 45.0, 0.0), corner_up(45.0, 0.0, 35.26);
  for (const Drop& drop :
       {Drop{edge_up, false}, Drop{edge_up, true}, Drop{corner_up, false}, Drop{corner_up, true},
        Drop{corner_up, true, 0.3, 0.1},
        Drop{corner_up + Vec3(0.0, 3.0, 0.0), true, 0.313, 0.15, Vec3(0.017, 0.0, 0.009)}}) {
    const bool as_mesh = drop.as_mesh;
    const Vec3& rotate = drop.rotate;
    SceneDef def = coarse_cloth_at(drop.height, as_mesh, GetParam());
    ColliderDef box;
    box.type = ColliderType::box;
    box.center = drop.center;
    box.half_extents = Vec3(0.12, 0.12, 0.12);
    box.rotate = rotate;
    box.friction = drop.friction;
    box.thickness = 0.005;
    ColliderDef ground;
    ground.type = ColliderType::plane;
    ground.center = Vec3(0.0, -0.1, 0.0);
    def.colliders = {as_mesh ? box_as_mesh(box) : box, ground};
    const auto c = box_corners(box);
    std::vector<std::pair<Vec3, Vec3>> edges;
    for (int k = 0; k < 8; ++k)
      for (int bit : {1, 2, 4})
        if (!(k & bit)) edges.emplace_back(c[k], c[k | bit]);
    Simulation sim(def);
    for (int f = 0; f < 90; ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      const int64_t crossings = segments_through_cloth(edges, sim);
      ASSERT_EQ(crossings, 0) << "a box edge passes through the cloth at frame " << f
                              << ", box rotated " << rotate.transpose()
                              << (as_mesh ? ", as a mesh" : "");
    }
  }
}

// A coarse cloth (5 cm cells) dropped onto a small open sheet (a table top as two triangles,
// turned so its rim crosses the cloth's cells at a slant, and tilted so the cloth slides over
// its lower rim): the rim is a blade, and no rim edge may pass through a cloth triangle at any
// frame's end. Without the rim's features every method let the rim cut through the cloth at
// frame 4. The slipperier sheet was found by varying the first: the irregular cloth sliding
// off its corner tore `xpbd` at frame 51 while a rim's push took an edge through the sheet for
// a cut of that rim (sharp_features_test.cpp). The last drop, found by a wider sweep (120
// drops), cut `implicit` at frame 37 while it took 4 steps a frame at the features.
TEST_P(EveryMethod, AnOpenSheetsRimNeverCutsThroughTheCloth) {
  struct Drop {
    double tilt, turn, friction;
    bool as_mesh;
  };
  for (const Drop& drop :
       {Drop{10.0, 30.0, 0.2, false}, Drop{10.0, 30.0, 0.2, true}, Drop{10.0, 30.0, 0.1, false},
        Drop{10.0, 30.0, 0.1, true}, Drop{7.5, 25.0, 0.1, true}}) {
    SceneDef def = coarse_cloth_at(0.05, drop.as_mesh, GetParam());
    const Mat3 turn = rotation_xyz(Vec3(drop.tilt, drop.turn, 0.0));
    const ColliderDef sheet = square_sheet(0.15, turn, drop.friction);
    const std::vector<Vec3>& rim = sheet.mesh->positions;
    def.colliders = {sheet};
    std::vector<std::pair<Vec3, Vec3>> edges;
    for (int k = 0; k < 4; ++k) edges.emplace_back(rim[k], rim[(k + 1) % 4]);
    Simulation sim(def);
    for (int f = 0; f < 90; ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      const int64_t crossings = segments_through_cloth(edges, sim);
      ASSERT_EQ(crossings, 0) << "the sheet's rim cuts through the cloth at frame " << f
                              << ", sheet tilted " << drop.tilt << "° and turned " << drop.turn
                              << "°, friction " << drop.friction
                              << (drop.as_mesh ? ", cloth as a mesh" : "");
    }
  }
}

// A thin sheet (an open mesh, wider than the cloth) under a cloth dropped from half a metre:
// it lands at 3 m/s, 5 cm a frame against the sheet's 5 mm thickness, and no cloth edge may
// pass through the sheet at any frame's end. Before the sheet kept each particle's side, `fast`
// (a step a frame) went through at frame 36.
TEST_P(EveryMethod, AClothDroppedOnAThinSheetStaysOnIt) {
  SceneDef def = coarse_cloth_at(0.5, false, GetParam());
  const ColliderDef sheet = square_sheet(0.5, Mat3::Identity(), 0.3);
  const ClothMesh& top = *sheet.mesh;
  def.colliders = {sheet};
  Simulation sim(def);
  for (int f = 0; f < 60; ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    const std::vector<Vec3>& x = sim.state().x;
    int64_t through = 0;
    for (const auto& [i, j] : triangle_edges(sim.model().triangles))
      for (const Triangle& t : top.triangles)
        through += testing_support::crosses(x[i], x[j], top.positions[t[0]], top.positions[t[1]],
                                            top.positions[t[2]]);
    ASSERT_EQ(through, 0) << "cloth edges through the sheet at frame " << f;
  }
  double lowest = 1.0;
  for (const Vec3& p : sim.state().x) lowest = std::min(lowest, p.y());
  EXPECT_GT(lowest, 0.0) << "the cloth ended below the sheet";
}

// A patch resting on a ball that the hand carries sideways (the viewer's Shift-drag) goes
// with it, held by friction; a panel change keeps the ball where the hand left it.
TEST_P(EveryMethod, TheHandCarriesABallAndTheClothOnIt) {
  const SceneDef def = patch_on_a_ball(GetParam());
  Simulation sim(def);
  while (sim.time() < 0.5 - 1e-9) ASSERT_TRUE(sim.step()) << sim.divergence();
  auto mean_x = [&] {
    double x = 0.0;
    for (const Vec3& p : sim.state().x) x += p.x() / sim.model().size();
    return x;
  };
  const double before = mean_x();
  // 0.2 m in 0.5 s, a step each frame (0.4 m/s), then held.
  for (int f = 1; f <= 30; ++f) {
    sim.move_collider(0, Vec3(0.2 * f / 30.0, 0.0, 0.0));
    sim.move_collider(7, Vec3(1.0, 0.0, 0.0));  // no such collider: ignored
    ASSERT_TRUE(sim.step()) << sim.divergence();
  }
  EXPECT_TRUE(sim.colliders().front().center.isApprox(Vec3(0.2, 0.0, 0.0), 1e-12));
  EXPECT_NEAR(mean_x() - before, 0.2, 0.05) << "the patch stayed behind";
  SceneDef changed = sim.def();
  changed.forces.air_drag = 0.01;
  ASSERT_TRUE(sim.reconfigure(changed));
  EXPECT_TRUE(sim.colliders().front().center.isApprox(Vec3(0.2, 0.0, 0.0), 1e-12));
  EXPECT_TRUE(sim.collider_offset(0).isApprox(Vec3(0.2, 0.0, 0.0), 1e-12));
}

INSTANTIATE_TEST_SUITE_P(Colliders, EveryMethod, ::testing::ValuesIn(testing_support::kVariants),
                         testing_support::variant_name);

// ---- Determinism ----------------------------------------------------------------------------

uint64_t hash_after(SceneDef def, int frames) {
  Simulation sim(def);
  for (int f = 0; f < frames; ++f) EXPECT_TRUE(sim.step()) << sim.divergence();
  uint64_t h = 1469598103934665603ULL;
  for (const Vec3& x : sim.state().x)
    for (int d = 0; d < 3; ++d) {
      uint64_t bits;
      std::memcpy(&bits, &x[d], sizeof bits);
      h = (h ^ bits) * 1099511628211ULL;
    }
  return h;
}

TEST(Determinism, AMovingBoxGivesTheSameBitsTwiceAndOnOneOrTwoThreads) {
  for (Method method : kAllMethods) {
    SceneDef def = testing_support::shipped("sphere");
    def.cloth.cols = def.cloth.rows = 96;  // above the size at which loops go parallel
    def.solver.method = method;
    ColliderDef box;
    box.type = ColliderType::box;
    box.center = Vec3(0.0, 0.3, 0.0);
    box.half_extents = Vec3(0.3, 0.6, 0.3);  // its top 0.1 m under the cloth, rising
    box.motion.keys = {{0.0, Vec3::Zero(), Vec3::Zero()},
                       {0.5, Vec3(0.2, 0.3, 0.0), Vec3(0, 45, 0)}};
    def.colliders = {box};
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
#endif
    const uint64_t one = hash_after(def, 3), again = hash_after(def, 3);
    EXPECT_EQ(one, again) << to_string(method);
#ifdef _OPENMP
    omp_set_num_threads(2);
    EXPECT_EQ(hash_after(def, 3), one) << to_string(method);
    omp_set_num_threads(threads);
#endif
  }
}

}  // namespace
}  // namespace drape
