// Self-collision (cloth.self_collision): the promise that no two triangles cross at the end of
// any frame, checked with the tests' own brute-force count, for every method; layers kept
// apart; determinism; the keys and their errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <nlohmann/json.hpp>
#include "brute_force_crossings.h"
#include "collision/layer_contact.h"
#include "collision/self_collision.h"
#include "drape/error.h"
#include "drape/self_intersections.h"
#include "drape/simulation.h"
#include "io/scene_io.h"
#include "long_range.h"
#include "test_scenes.h"
#include "variants.h"

namespace drape {
namespace {

using testing_support::brute_force_crossings;
using testing_support::Variant;

// The shipped pile, small: a cloth dropped edge first so that it folds onto itself.
SceneDef small_pile(int n) {
  SceneDef def = testing_support::shipped("pile");
  def.cloth.cols = def.cloth.rows = n;
  def.duration = 2.5;
  return def;
}

// Two separate square sheets of n × n quads, 1 m wide: one lying 2 cm above the ground, the
// other `top` m above it, turned by `tilt` degrees about x; self-collision on, 1 cm thick.
SceneDef two_sheets(int n, double tilt, double top = 0.3) {
  auto sheets = std::make_shared<ClothMesh>();
  const double turn = tilt * 3.14159265358979 / 180.0;
  for (const double y : {0.02, top}) {
    const int32_t first = static_cast<int32_t>(sheets->positions.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double z = -0.5 + double(j) / n;
        const double rise = y == top ? z * std::sin(turn) : 0.0;
        sheets->positions.push_back(
            Vec3(-0.5 + double(i) / n, y + rise, y == top ? z * std::cos(turn) : z));
      }
    auto at = [&](int i, int j) { return first + j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        sheets->triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        sheets->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      }
  }
  SceneDef def;
  def.cloth.mesh = sheets;
  def.cloth.mesh_file = "two sheets";
  def.cloth.pins.clear();
  def.cloth.perturbation = 0.0;
  def.cloth.self_collision.enabled = true;
  def.cloth.self_collision.thickness = 0.01;
  ColliderDef ground;
  ground.type = ColliderType::plane;
  ground.thickness = 0.005;
  def.colliders = {ground};
  return def;
}

class SelfCollisionEveryMethod : public ::testing::TestWithParam<Variant> {};

// Without self-collision the pile ends with its triangles through each other (the test can
// fail); with it, no frame ends with a crossing pair, counted by the tests' own brute force.
// A tilted sheet dropped onto a flat one held up by its corners goes through it without
// self-collision (so the test can fail); with it, no frame ends with a crossing pair, counted by
// the tests' own brute force, on two sheets and on a cloth folding onto itself.
TEST_P(SelfCollisionEveryMethod, NoFrameEndsWithCrossingTriangles) {
  // The lower sheet held up by its four corners, 15 cm up: the upper one falls into it.
  SceneDef sheets = testing_support::with(two_sheets(8, 20.0), GetParam());
  sheets.cloth.transform.translate = Vec3(0.0, 0.13, 0.0);
  for (const int32_t corner : {0, 8, 9 * 8, 9 * 9 - 1})
    sheets.cloth.pins.push_back(Pin::at_vertex(corner));
  sheets.cloth.long_range.enabled = sheets.solver.line_passes > 0;  // line passes need it
  sheets.duration = 1.0;
  sheets.cloth.self_collision.enabled = false;
  Simulation free(sheets);
  int64_t crossings_without = 0;
  for (int64_t f = 0; f < frame_count(sheets) && free.step(); ++f)
    crossings_without =
        std::max(crossings_without, brute_force_crossings(free.model().triangles, free.state().x));
  ASSERT_FALSE(free.diverged()) << free.divergence();
  EXPECT_GT(crossings_without, 0) << "the sheets no longer pass through each other without "
                                     "self-collision: the test tests nothing";

  sheets.cloth.self_collision.enabled = true;
  for (const SceneDef& def : {sheets, testing_support::with(small_pile(12), GetParam())}) {
    Simulation sim(def);
    for (int64_t f = 0; f < frame_count(def); ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      ASSERT_EQ(brute_force_crossings(sim.model().triangles, sim.state().x), 0)
          << def.cloth.mesh_file << " frame " << f;
    }
    ASSERT_NE(sim.self_collision(), nullptr);
    EXPECT_EQ(sim.self_collision()->left, 0);
    EXPECT_LT(sim.diagnostics().max_penetration, 1e-9);  // and the ground still holds it
  }
}

// The standard stress test: a strip twisted by its two ends turning opposite ways (the
// shipped twist, small), which without self-collision passes through itself.
TEST_P(SelfCollisionEveryMethod, ATwistedStripNeverCrossesItself) {
  SceneDef def = testing_support::with(testing_support::shipped("twist"), GetParam());
  def.cloth.long_range.enabled = def.solver.line_passes > 0;  // line passes need it
  def.cloth.cols = 24, def.cloth.rows = 10;
  if (def.solver.method != Method::xpbd) def.solver.substeps = def.solver.stiff_sweeps = 0;
  def.duration = 3.0;
  Simulation sim(def);
  for (int64_t f = 0; f < frame_count(def); ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    ASSERT_EQ(brute_force_crossings(sim.model().triangles, sim.state().x), 0) << "frame " << f;
  }
}

// A flag on a pole that is carried 1.2 m and turned a quarter turn in a second, held by
// long-range attachments: at every frame's end each particle lies within its limits of its pins
// where they are now, not where they started (from there it lies 25 times its limit away by
// the end). Measured beyond the limits at worst: symplectic 0.3%, implicit 0.4% (the tethers
// projected one after another while several pull), fast and xpbd none; held to 1%. Line
// passes end with the chains' solve, after the attachments, and their worst is one frame's
// peak as the pole starts that moves with the rounding: line passes 2.4% and auto 3.8% at
// -O3, 6.0% and 3.4% at -O1 (the sanitizers' build); held to 10%. (Attachments after the
// passes too would hold them to 0, but raise hang-lr's strain, 0.70% to 0.83% at 128², and
// auto's cost there 13%.)
TEST_P(SelfCollisionEveryMethod, LongRangeAttachmentsFollowMovingPins) {
  SceneDef def = testing_support::with(io::parse_scene(nlohmann::json::parse(R"({
      "cloth": {"size": [1.0, 0.75], "resolution": [16, 12], "origin": [-0.5, 1.5, 0.0],
                "orientation": "vertical", "long_range": true,
                "pins": [{"box": {"min": [-0.51, 1.49, -0.01], "max": [0.51, 1.51, 0.01]},
                          "motion": {"keys": [{"t": 0},
                                              {"t": 1, "translate": [1.0, 0.3, 0.5],
                                               "rotate": [0, 90, 0]}]}}]},
      "forces": {"gravity": [0, -9.81, 0]}, "duration": 1.5})"),
                                                       "flag"),
                                       GetParam());
  Simulation sim(def);
  LongRange attachments;
  attachments.prepare(sim.model(), sim.state(), def.cloth.long_range);
  ASSERT_TRUE(attachments.active());
  const std::vector<Vec3> start = sim.state().x;
  // How far beyond its limits particle i lies from its tethers' pins at positions `pins`, as a
  // fraction of the limit.
  auto beyond = [&](const std::vector<Vec3>& pins, int32_t i) {
    double most = -1.0;
    for (int t = 0; t < attachments.tethers() && attachments.pin(i, t) >= 0; ++t) {
      const double limit = attachments.limit(i, t);
      most = std::max(most, (sim.state().x[i] - pins[attachments.pin(i, t)]).norm() / limit - 1.0);
    }
    return most;
  };
  double worst = 0.0, behind = 0.0;
  for (int64_t f = 0; f < frame_count(def); ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    for (int32_t i = 0; i < sim.model().size(); ++i) {
      if (sim.state().pinned[i]) continue;
      worst = std::max(worst, beyond(sim.state().x, i));
      behind = std::max(behind, beyond(start, i));
    }
  }
  const bool lines = def.solver.line_passes > 0 || def.solver.method == Method::automatic;
  EXPECT_LT(worst, lines ? 0.10 : 0.01) << "beyond a limit from the pins where they are";
  EXPECT_GT(behind, 10.0) << "beyond a limit from where the pins started: the check is void";
}

// A pile comes to rest instead of creeping or jittering: the shipped `pile.json` (32², dropped
// edge-first so that it folds onto itself on the ground) with each method lies still in its
// tenth second, its centre moving under 1 mm between 9 and 10 s (measured: symplectic 0.070,
// implicit 0.027, xpbd 0.040 mm, single 0.041 mm). It replaces a test of `auto` on a 16² pile
// with a 3 cm/s bound, which the shipped pile's creep passed.
TEST_P(SelfCollisionEveryMethod, TheShippedPileLiesStillInItsTenthSecond) {
  const Variant v = GetParam();
  if (v.method == Method::automatic || v.line_passes > 0)
    GTEST_SKIP() << "NOT reached with xpbd's line passes (auto takes them): the pile creeps "
                    "along the ground, 22 mm (auto) and 7.5 mm (3 passes) between 9 and 10 s "
                    "(README, Self-collision)";
  if (v.method == Method::fast)
    GTEST_SKIP() << "NOT reached with fast: the cloth stands on its edge like a board for 4 s "
                    "and is still toppling at 10 s, 68 mm between 9 and 10 s: its springs' "
                    "damping acts across them too (README, Self-collision)";
  const SceneDef def = testing_support::with(testing_support::shipped("pile"), GetParam());
  Simulation sim(def);
  auto centre = [&] {
    Vec3 c = Vec3::Zero();
    for (const Vec3& x : sim.state().x) c += x / sim.model().size();
    return c;
  };
  Vec3 before = Vec3::Zero();
  for (int f = 0; f < 600; ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    if (f + 1 == 540) before = centre();
  }
  const double moved = (centre() - before).norm();
  std::printf("the pile's centre moved %.3g mm between 9 and 10 s\n", 1e3 * moved);
  EXPECT_LT(moved, 1e-3);
  EXPECT_EQ(count_self_intersections(sim.model().triangles, sim.state().x), 0);
}

INSTANTIATE_TEST_SUITE_P(Methods, SelfCollisionEveryMethod,
                         ::testing::ValuesIn(testing_support::kVariants),
                         testing_support::variant_name);

// Two separate sheets, one dropped flat onto the other lying on the ground: the top one comes
// to rest on the bottom one, a thickness above it, instead of falling through to the ground.
TEST(SelfCollision, ASheetDroppedOnAnotherRestsOnItAThicknessAbove) {
  const int n = 10;
  SceneDef def = two_sheets(n, 0.0);
  def.solver.method = Method::xpbd;
  def.solver.substeps = 20;
  def.duration = 1.5;
  Simulation sim(def);
  for (int64_t f = 0; f < frame_count(def); ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const int32_t per_sheet = (n + 1) * (n + 1);
  double bottom_highest = -1.0, top_lowest = 1.0;
  for (int32_t i = 0; i < per_sheet; ++i) {
    bottom_highest = std::max(bottom_highest, sim.state().x[i].y());
    top_lowest = std::min(top_lowest, sim.state().x[per_sheet + i].y());
  }
  EXPECT_NEAR(bottom_highest, 0.005, 2e-3);            // the bottom sheet on the ground
  EXPECT_GT(top_lowest - bottom_highest, 0.8 * 0.01);  // the top one a thickness above it
  EXPECT_LT(top_lowest, 0.005 + 0.02);                 // and resting on it, not floating
  EXPECT_LT(sim.diagnostics().kinetic_energy, 1e-4);   // at rest
}

// Coulomb friction between layers: a sheet resting on another, both on a slope of angle θ
// (the lower one held by the ground's friction), stays when tan θ < μ and slides when
// tan θ > μ.
TEST(SelfCollision, ASheetOnASlopeStaysOrSlidesByTheLayersFriction) {
  const double mu = 0.5;
  auto slid = [&](double degrees) {
    SceneDef def = two_sheets(8, 0.0, 0.032);
    def.cloth.self_collision.friction = mu;
    def.cloth.transform.rotate = Vec3(degrees, 0.0, 0.0);
    const double turn = degrees * 3.14159265358979 / 180.0;
    def.colliders[0].normal = Vec3(0.0, std::cos(turn), std::sin(turn));
    def.colliders[0].friction = 3.0;  // the lower sheet stays put
    def.solver.method = Method::xpbd;
    def.solver.substeps = 20;
    def.duration = 1.0;
    Simulation sim(def);
    const std::vector<Vec3> start = sim.state().x;
    for (int64_t f = 0; f < frame_count(def); ++f) EXPECT_TRUE(sim.step()) << sim.divergence();
    // How far the upper sheet moved relative to the lower one, on average.
    const size_t half = start.size() / 2;
    Vec3 lower = Vec3::Zero(), upper = Vec3::Zero();
    for (size_t i = 0; i < half; ++i) {
      lower += sim.state().x[i] - start[i];
      upper += sim.state().x[half + i] - start[half + i];
    }
    // Along the slope only: the upper sheet also settles a few mm onto the lower one.
    const Vec3 moved = (upper - lower) / static_cast<double>(half);
    const Vec3 normal = def.colliders[0].normal;
    return (moved - moved.dot(normal) * normal).norm();
  };
  EXPECT_LT(slid(20.0), 0.005);  // tan 20° = 0.36 < 0.5: stays
  EXPECT_GT(slid(35.0), 0.1);    // tan 35° = 0.70 > 0.5: slides (1.2 m/s² for a second: ~0.6 m)
}

// The solver's pass over the layers the stage left touching (HeldLayers), on one vertex over a
// level triangle, against the closed forms of an inelastic position-based contact with
// Coulomb friction: the vertex ends a thickness above; what it fell this substep is undone as a
// move (no velocity toward or away from the triangle), what it lay too close before as a shift
// (no velocity either); its slide is cancelled while within μ × the fall undone, else shortened
// by exactly that.
namespace {
struct TestCloth {
  std::vector<Vec3> base, move;
  std::vector<double> inverse_mass;
  Vec3 position(int32_t i) const { return base[i] + move[i]; }
  double inv_mass(int32_t i) const { return inverse_mass[i]; }
  Vec3 moved(int32_t i) const { return move[i]; }
  void add(int32_t i, const Vec3& d) { move[i] += d; }
  void shift(int32_t i, const Vec3& d) { base[i] += d; }
};

// Vertex 0 started the substep `gap` above the triangle 1-2-3 (level at y = 0, its normal
// (x2 − x1) × (x3 − x1) = +y) and moved by `step` since; the triangle's corners are fixed, or
// rest on the ground (grounded: they fell by `fall` this substep, which the ground will undo).
TestCloth held_vertex(double gap, const Vec3& step, bool grounded, double fall, double h,
                      double mu) {
  TestCloth cloth;
  cloth.base = {Vec3(0.2, gap, 0.2), Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0)};
  cloth.move.assign(4, grounded ? Vec3(0, -fall, 0) : Vec3::Zero());
  cloth.move[0] = step;
  cloth.inverse_mass = {2.0, grounded ? 3.0 : 0.0, grounded ? 3.0 : 0.0, grounded ? 3.0 : 0.0};
  HeldLayers held;
  held.thickness = h;
  held.friction = mu;
  held.pairs.push_back({{0, 1, 2, 3}, 0, 1, uint8_t(grounded ? 0b1110 : 0)});
  held.apply(cloth);
  return cloth;
}
}  // namespace

TEST(HeldLayers, AVertexEndsAThicknessAboveWithNoNormalVelocityAndCoulombFriction) {
  const double h = 0.01, mu = 0.5;
  for (const bool grounded : {false, true}) {
    // Grounded corners fell 0.2h with the vertex; its thickness is kept from where they are.
    const double sink = grounded ? 0.2 * h : 0.0;
    // Started 0.4h above and fell 0.2h: 0.2h of the fall is undone as a move, the rest of the
    // depth (where it lay too close before) as a shift.
    TestCloth c = held_vertex(0.4 * h, Vec3(0, -0.2 * h, 0), grounded, sink, h, mu);
    EXPECT_NEAR(c.position(0).y(), h - sink, 1e-15) << grounded;
    EXPECT_NEAR(c.move[0].y(), 0.0, 1e-15) << grounded;
    EXPECT_NEAR(c.base[0].y(), h - sink, 1e-15) << grounded;
    const TestCloth start = held_vertex(2.0 * h, Vec3::Zero(), grounded, sink, h, mu);
    for (int k = 1; k < 4; ++k) {  // grounded corners do not give way; fixed ones cannot
      EXPECT_EQ(c.base[k], start.base[k]);
      EXPECT_EQ(c.move[k], Vec3(0, -sink, 0));
    }
    // A vertex a thickness above the corners at the substep's start, fallen 0.2h: a slide
    // within μ × that fall (0.1h) is cancelled (a grounded corner's own fall is not an
    // approach)...
    const double gap = h - sink;
    c = held_vertex(gap, Vec3(0.08 * h, -0.2 * h, 0.0), grounded, sink, h, mu);
    EXPECT_NEAR(c.position(0).y(), h - sink, 1e-15) << grounded;
    EXPECT_NEAR(c.move[0].x(), 0.0, 1e-15) << grounded;
    // ... a larger one is shortened by exactly that.
    c = held_vertex(gap, Vec3(0.3 * h, -0.2 * h, 0.0), grounded, sink, h, mu);
    EXPECT_NEAR(c.move[0].x(), 0.2 * h, 1e-15) << grounded;
  }
  // Beyond the thickness, nothing; deeper than a thickness on the other side (it came round an
  // edge, not through the face), nothing: the stage's business.
  for (const double gap : {1.5, -1.5}) {
    const TestCloth c = held_vertex(gap * h, Vec3(0, -0.2 * h, 0), false, 0.0, h, mu);
    EXPECT_NEAR((c.position(0) - Vec3(0.2, (gap - 0.2) * h, 0.2)).norm(), 0.0, 1e-15) << gap;
  }
}

// A frame is split into collision steps only where layers move past each other: a sheet
// turned a quarter turn in one frame, close to nothing of itself, needs one step; a sheet
// sliding over another half a thickness below it needs one per half thickness it slides.
TEST(SelfCollision, AFrameIsSplitOnlyWhereLayersMovePastEachOther) {
  const double h = 0.01;
  SceneDef def = two_sheets(8, 0.0, 0.02 + 0.5 * h);
  def.colliders.clear();
  Simulation sim(def);
  const ClothModel& model = sim.model();
  const size_t half = model.size() / 2;
  SelfCollision collision;
  collision.prepare(model, h, 0.0);
  auto parts_after = [&](const std::vector<Vec3>& start, const std::vector<Vec3>& end) {
    ClothState state = sim.state();
    state.x = end;
    collision.resolve(model, start, {}, 1.0 / 60.0, state, false);
    return collision.parts_for(collision.near_motion());
  };
  // The lower sheet alone (the upper one far above it) turned a quarter turn about y, its
  // rim moving 0.7 m: nothing of it comes close to anything else of it.
  std::vector<Vec3> start = sim.state().x, turned = start;
  const Eigen::Matrix3d quarter = Eigen::AngleAxisd(1.5707963, Vec3::UnitY()).toRotationMatrix();
  for (size_t i = half; i < start.size(); ++i) start[i].y() += 1.0, turned[i].y() += 1.0;
  for (size_t i = 0; i < half; ++i) turned[i] = quarter * start[i];
  EXPECT_EQ(parts_after(start, turned), 1);
  // The upper sheet slides 2.4 thicknesses over the lower one: five steps of half a thickness.
  start = sim.state().x;
  std::vector<Vec3> slid = start;
  for (size_t i = half; i < start.size(); ++i) slid[i].x() += 2.4 * h;
  EXPECT_EQ(parts_after(start, slid), 5);
}

// The contacts' pushes move layers, not the threads between them, after a method that held
// the layers in its substeps. A small pile (xpbd, 2.5 s) is squeezed to 80% of its height in
// one frame, its layers pressed into each other as a solver's step that let them sink would
// leave them; the stage pushes them apart again (by up to 10 mm), and every thread
// (structural spring) ends within 1.5% of the length the squeeze left it (measured 0.93%).
// Without the threads kept between the passes (as after the methods that leave layers to the
// stage) one ends 2.97% longer or shorter.
TEST(SelfCollision, PushesApartLeaveTheThreadsAsTheSolverLeftThem) {
  SceneDef def = small_pile(16);
  def.solver.method = Method::xpbd;
  Simulation sim(def);
  for (int64_t f = 0; f < frame_count(def); ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const ClothModel& model = sim.model();
  const std::vector<Vec3> start = sim.state().x;
  std::vector<Vec3> squeezed = start;
  for (Vec3& x : squeezed) x.y() *= 0.8;
  const double h = self_collision_thickness(def.cloth.self_collision, model);
  const std::vector<Collider> ground = make_colliders(def.colliders);
  auto changed = [&](bool threads_kept) {
    SelfCollision collision;
    collision.prepare(model, h, def.cloth.self_collision.friction);
    ClothState state = sim.state();
    state.x = squeezed;
    EXPECT_TRUE(collision.resolve(model, start, ground, def.solver.dt, state, threads_kept));
    EXPECT_GT(collision.report().contacts, 100);
    EXPECT_EQ(collision.report().zone_vertices + collision.report().frozen_vertices, 0);
    double moved = 0.0, worst = 0.0;
    for (const Spring& s : model.springs) {
      if (s.kind != SpringKind::structural) continue;
      moved = std::max(moved, (state.x[s.i] - squeezed[s.i]).norm());
      const double before = (squeezed[s.j] - squeezed[s.i]).norm();
      worst = std::max(worst, std::abs((state.x[s.j] - state.x[s.i]).norm() / before - 1.0));
    }
    std::printf("threads %s: layers moved up to %.3g mm; threads changed by %.3g%% at most\n",
                threads_kept ? "kept" : "not kept", 1e3 * moved, 100.0 * worst);
    EXPECT_GT(moved, 0.25 * h);  // the pushes did move the layers
    return worst;
  };
  EXPECT_LT(changed(true), 0.015);
  EXPECT_GT(changed(false), 0.02);
}

// Where every triangle's inradius is under the reach (twice the thickness), a triangle pierced
// by another's edge always leaves a contact for the search to find, so a frame with no contact
// has no crossing either (the stage then skips its crossing check): no point inside a triangle
// is farther than its inradius from all of its edges. Random triangles of 0.5 to 1.5 cm
// (inradii up to about 0.4 cm) pierced at random points inside by an edge of random
// direction, 2 mm thick (a reach of 4 mm); each pair crosses by the tests' own count.
TEST(SelfCollision, EveryCrossingLeavesAContactWhereTrianglesAreSmallerThanTheReach) {
  SceneDef def = two_sheets(1, 0.0);
  def.colliders.clear();
  Simulation sim(def);
  const ClothModel& model = sim.model();
  ASSERT_EQ(model.size(), 8);
  const double h = 0.002;
  SelfCollision collision;
  collision.prepare(model, h, 0.0);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto direction = [&] {
    Vec3 d;
    do d = Vec3(unit(random), unit(random), unit(random));
    while (d.norm() < 0.1 || d.norm() > 1.0);
    return Vec3(d.normalized());
  };
  int checked = 0;
  for (int k = 0; k < 2000; ++k) {
    // The first sheet: a random small quad; triangle 0 of it is pierced.
    std::vector<Vec3> x(8);
    for (int v = 0; v < 4; ++v) x[v] = 0.0075 * Vec3(unit(random), unit(random), unit(random));
    const Triangle& pierced = model.triangles[0];
    const Vec3 &a = x[pierced[0]], &b = x[pierced[1]], &c = x[pierced[2]];
    const double area2 = (b - a).cross(c - a).norm();
    const double inradius = area2 / ((b - a).norm() + (c - b).norm() + (a - c).norm());
    if (inradius < 1e-4 || inradius >= 0.999 * 2.0 * h) continue;
    // A point inside it and an edge of the second sheet through it, its other corners away.
    double u = std::abs(unit(random)), v = std::abs(unit(random));
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    const Vec3 inside = a + u * (b - a) + v * (c - a);
    const Vec3 along = direction();
    const Triangle& piercing = model.triangles[2];  // the second sheet's first triangle
    x[piercing[0]] = inside - (0.002 + 0.01 * std::abs(unit(random))) * along;
    x[piercing[1]] = inside + (0.002 + 0.01 * std::abs(unit(random))) * along;
    for (int w = 4; w < 8; ++w)
      if (w != piercing[0] && w != piercing[1]) x[w] = inside + 0.05 * direction();
    if (brute_force_crossings(model.triangles, x) == 0) continue;  // grazing: not inside
    ClothState state = sim.state();
    state.x = x;
    // Every particle held, so that no push undoes the crossing before the check for crossings.
    state.inv_mass.assign(state.inv_mass.size(), 0.0);
    collision.resolve(model, x, {}, 1.0 / 60.0, state, false);
    EXPECT_GT(collision.report().contacts, 0) << "case " << k << ", inradius " << inradius;
    // ... and the check for crossings, which trusts that, runs and sees this one.
    EXPECT_GT(collision.report().crossings, 0) << "case " << k << ", inradius " << inradius;
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

// A pin with a motion: its particles are where the keyed rotation about their centre puts
// them, at every frame (here half a turn about x over a second, held after).
TEST(MovingPins, FollowTheirKeys) {
  SceneDef def = testing_support::shipped("twist");
  def.cloth.self_collision.enabled = false;
  def.duration = 1.5;
  Simulation sim(def);
  const std::vector<int32_t> end = pin_particles(def.cloth, sim.model(), 0);
  std::vector<Vec3> start;
  Vec3 centre = Vec3::Zero();
  for (const int32_t i : end) start.push_back(sim.state().x[i]), centre += sim.state().x[i];
  centre /= static_cast<double>(end.size());
  const double key_time = def.cloth.pins[0].motion.keys.back().t;
  const double key_angle = def.cloth.pins[0].motion.keys.back().rotate.x();
  for (int64_t f = 0; f < frame_count(def); ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    // The keys are evenly spaced and about x alone: the angle grows linearly.
    const double angle =
        key_angle * std::min(1.0, sim.time() / key_time) * 3.14159265358979 / 180.0;
    const Eigen::AngleAxisd turn(angle, Vec3::UnitX());
    for (size_t j = 0; j < end.size(); ++j)
      ASSERT_LT((sim.state().x[end[j]] - (centre + turn * (start[j] - centre))).norm(), 1e-9)
          << "frame " << f;
  }
}

TEST(MovingPins, SceneKeys) {
  const SceneDef def = io::parse_scene(nlohmann::json::parse(R"({"cloth": {"pins": [
      {"pin": "top-left", "motion": {"keys": [{"t": 0, "translate": [0, 0, 0]},
                                              {"t": 1, "translate": [0, 1, 0]}]}},
      {"box": {"min": [0, 1, -1], "max": [1, 3, 1]},
       "motion": {"keys": [{"t": 0}, {"t": 2, "rotate": [0, 90, 0]}], "pivot": [0, 2, 0]}},
      "top-right"]}})"),
                                       "test");
  ASSERT_EQ(def.cloth.pins.size(), 3u);
  EXPECT_EQ(def.cloth.pins[0].motion.keys.size(), 2u);
  EXPECT_EQ(def.cloth.pins[0].kind, PinKind::grid);
  EXPECT_TRUE(def.cloth.pins[1].motion.has_pivot);
  EXPECT_FALSE(def.cloth.pins[2].motion.moves());
  const SceneDef again = io::parse_scene(io::to_json(def), "again");
  ASSERT_EQ(again.cloth.pins.size(), 3u);
  EXPECT_EQ(again.cloth.pins[0].motion.keys[1].translate, Vec3(0, 1, 0));
  EXPECT_EQ(again.cloth.pins[1].motion.pivot, Vec3(0, 2, 0));
  // Keys whose times do not increase are refused, naming the pin.
  try {
    io::parse_scene(nlohmann::json::parse(R"({"cloth": {"pins": [{"pin": "top-left",
        "motion": {"keys": [{"t": 1}, {"t": 1}]}}]}})"),
                    "test");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cloth.pins[0].motion"), std::string::npos) << e.what();
  }
}

TEST(SelfCollision, SameBitsTwiceAndOnOneOrTwoThreads) {
  SceneDef def = small_pile(16);
  def.duration = 1.5;
  auto run = [&](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    Simulation sim(def);
    for (int64_t f = 0; f < frame_count(def); ++f) sim.step();
    return sim.state().x;
  };
  const std::vector<Vec3> a = run(1), b = run(2), c = run(2);
#ifdef _OPENMP
  omp_set_num_threads(omp_get_num_procs());
#endif
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i], b[i]) << "particle " << i << ": one thread against two";
    ASSERT_EQ(b[i], c[i]) << "particle " << i << ": two runs";
  }
}

// Off by default, and off it changes nothing: the state is bit for bit the one without it.
// What self-collision holds (its boxes, grids, patches, crossing search and the contacts it
// finds, which grow as the cloth piles up) is counted by memory() and stays under the
// estimate a run's memory budget is checked against before anything is built, without being
// far from it: a pile at two sizes, checked every half second of its folding.
TEST(SelfCollision, MemoryStaysUnderTheEstimate) {
  for (int n : {24, 48}) {
    const SceneDef def = small_pile(n);
    Simulation sim(def);
    const int64_t off = [&] {
      SceneDef without = def;
      without.cloth.self_collision.enabled = false;
      return Simulation(without).memory().total();
    }();
    for (int f = 1; f <= 180; ++f) {
      ASSERT_TRUE(sim.step()) << sim.divergence();
      if (f % 30 != 0) continue;
      const int64_t total = sim.memory().total();
      EXPECT_GT(total, off + sim.model().size() * int64_t{800}) << n << "², frame " << f;
      EXPECT_LE(total, estimated_memory(def)) << n << "², frame " << f;
      EXPECT_GE(3 * total, estimated_memory(def)) << n << "², frame " << f;
    }
  }
}

TEST(SelfCollision, OffByDefault) {
  SceneDef def;
  EXPECT_FALSE(def.cloth.self_collision.enabled);
  Simulation sim(def);
  EXPECT_EQ(sim.self_collision(), nullptr);
}

TEST(SelfCollision, SceneKeys) {
  auto parse = [](const std::string& cloth) {
    return io::parse_scene(nlohmann::json::parse(R"({"cloth": {"self_collision": )" + cloth + "}}"),
                           "test");
  };
  EXPECT_FALSE(parse("false").cloth.self_collision.enabled);
  EXPECT_TRUE(parse("true").cloth.self_collision.enabled);
  const SceneDef def = parse(R"({"thickness": 0.004, "friction": 0.5})");
  EXPECT_TRUE(def.cloth.self_collision.enabled);
  EXPECT_EQ(def.cloth.self_collision.thickness, 0.004);
  EXPECT_EQ(def.cloth.self_collision.friction, 0.5);
  // Written back and read again, the same.
  const SceneDef again = io::parse_scene(io::to_json(def), "again");
  EXPECT_EQ(again.cloth.self_collision.thickness, 0.004);
  EXPECT_EQ(again.cloth.self_collision.friction, 0.5);

  auto error_of = [&](const std::string& cloth) {
    try {
      Simulation sim(parse(cloth));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("3").find("cloth.self_collision"), std::string::npos);
  EXPECT_NE(error_of(R"({"thickness": -1})").find("cloth.self_collision.thickness"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"friction": -0.1})").find("cloth.self_collision.friction"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"thikness": 0.01})").find("thikness"), std::string::npos);
  // The default cloth's edges are 6.45 cm: 4 cm is more than half.
  const std::string thick = error_of(R"({"thickness": 0.04})");
  EXPECT_NE(thick.find("cloth.self_collision.thickness"), std::string::npos) << thick;
  EXPECT_NE(thick.find("half the cloth's mean edge"), std::string::npos) << thick;
}

}  // namespace
}  // namespace drape
