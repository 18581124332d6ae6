// Cloth of any shape: the model a mesh builds (springs, masses, colours, the chain cover, the
// attachments' geodesics), and every method on meshes against closed forms, conservation laws
// and each other. Tolerances are stated next to each check with their reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <set>

#include "drape/error.h"
#include "drape/simulation.h"
#include "equilibrium.h"
#include "long_range.h"
#include "parallel.h"
#include "solvers/xpbd/chain_cover.h"
#include "variants.h"

namespace drape {
namespace {

using testing_support::kVariants;
using testing_support::momentum;
using testing_support::momentum_allowance;
using testing_support::single;
using testing_support::Variant;
using testing_support::variant_name;
using testing_support::with;

std::shared_ptr<const ClothMesh> share(ClothMesh m) {
  return std::make_shared<const ClothMesh>(std::move(m));
}

/// A cloth of `mesh` with nothing but what a test turns on: no gravity, drag, wind, pins or
/// perturbation (as testing_support::bare for the grid).
SceneDef bare_mesh(ClothMesh mesh) {
  SceneDef def;
  def.cloth.mesh = share(std::move(mesh));
  def.cloth.pins.clear();
  def.cloth.perturbation = 0.0;
  def.forces.gravity = Vec3::Zero();
  def.forces.air_drag = 0.0;
  return def;
}

std::vector<std::pair<int32_t, int32_t>> structural_edges(const ClothModel& m) {
  std::vector<std::pair<int32_t, int32_t>> edges;
  for (const Spring& s : m.springs)
    if (s.kind == SpringKind::structural) edges.push_back({s.i, s.j});
  return edges;
}

// ---- The model --------------------------------------------------------------------------------

TEST(MeshModel, EdgesAreStructuralSharedEdgesBendAndMassGoesByArea) {
  // A unit square as two triangles sharing the diagonal 0–2: five edges, one of them shared,
  // so one bending spring between the far corners 1 and 3. Each triangle has area ½; a vertex
  // carries a third of each triangle around it: 0 and 2 touch both (⅓ kg of a 1 kg cloth),
  // 1 and 3 one (⅙ kg).
  ClothMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  SceneDef def = bare_mesh(m);
  const ClothModel model = build_model(def.cloth);
  EXPECT_FALSE(model.grid.present());
  int structural = 0, bending = 0;
  for (const Spring& s : model.springs) {
    EXPECT_NE(s.kind, SpringKind::shear);  // a mesh's edges carry shear
    if (s.kind == SpringKind::structural) {
      ++structural;
      EXPECT_NEAR(s.rest, (m.positions[s.j] - m.positions[s.i]).norm(), 1e-15);
      EXPECT_EQ(s.stiffness, def.cloth.structural.stiffness);
    } else {
      ++bending;
      EXPECT_EQ(std::min(s.i, s.j), 1);
      EXPECT_EQ(std::max(s.i, s.j), 3);
      EXPECT_NEAR(s.rest, std::sqrt(2.0), 1e-15);
      EXPECT_EQ(s.stiffness, def.cloth.bending.stiffness);
    }
  }
  EXPECT_EQ(structural, 5);
  EXPECT_EQ(bending, 1);
  const double third = 1.0 / 3.0, sixth = 1.0 / 6.0;
  EXPECT_NEAR(model.mass[0], third, 1e-15);
  EXPECT_NEAR(model.mass[1], sixth, 1e-15);
  EXPECT_NEAR(model.mass[2], third, 1e-15);
  EXPECT_NEAR(model.mass[3], sixth, 1e-15);
  EXPECT_NEAR(model.mean_edge, (4.0 + std::sqrt(2.0)) / 5.0, 1e-15);
}

TEST(MeshModel, TransformScalesThenRotatesAboutXThenYThenZThenTranslates) {
  MeshTransform t;
  t.rotate = Vec3(90, 0, 0);
  EXPECT_LT((t.apply(Vec3::UnitY()) - Vec3::UnitZ()).norm(), 1e-15);  // +y turns into +z
  t.rotate = Vec3(90, 90, 0);  // x first: +y → +z; then y: +z → +x
  EXPECT_LT((t.apply(Vec3::UnitY()) - Vec3::UnitX()).norm(), 1e-15);
  t.rotate = Vec3(90, 0, 0);
  t.scale = Vec3(2, 1, 1);
  t.translate = Vec3(1, 2, 3);
  // (1, 1, 0) scaled to (2, 1, 0), turned about x to (2, 0, 1), moved to (3, 2, 4).
  EXPECT_LT((t.apply(Vec3(1, 1, 0)) - Vec3(3, 2, 4)).norm(), 1e-15);
  // The rest shape is the transformed mesh's: rest lengths scale with it.
  SceneDef def = bare_mesh(shapes::jittered_grid(1.0, 6));
  def.cloth.transform.scale = Vec3(2, 2, 2);
  const ClothModel big = build_model(def.cloth);
  def.cloth.transform.scale = Vec3::Ones();
  const ClothModel small = build_model(def.cloth);
  ASSERT_EQ(big.springs.size(), small.springs.size());
  for (size_t k = 0; k < big.springs.size(); ++k)
    EXPECT_NEAR(big.springs[k].rest, 2.0 * small.springs[k].rest, 1e-14);
}

TEST(MeshModel, AVertexOfValenceOverSixtyThreeLeavesItsExtraSpringsToOneThread) {
  // A disc whose centre is the corner of 100 triangles: 100 structural springs meet there, but
  // only 63 colours are kept independent. The colours up to independent_colours must share no
  // particle; the rest (one last colour) holds what they could not take; every spring is kept.
  const ClothModel m = build_model(bare_mesh(shapes::disc(1.0, 2, 100)).cloth);
  EXPECT_LT(m.independent_colours, m.colours());  // a last colour for one thread
  std::multiset<std::pair<int32_t, int32_t>> all;
  for (int c = 0; c < m.colours(); ++c) {
    std::vector<int> seen(m.size(), 0);
    for (int32_t s = m.colour_begin[c]; s < m.colour_begin[c + 1]; ++s) {
      all.insert({m.springs[s].i, m.springs[s].j});
      if (!m.colour_is_independent(c)) continue;
      EXPECT_EQ(seen[m.springs[s].i]++, 0) << "colour " << c;
      EXPECT_EQ(seen[m.springs[s].j]++, 0) << "colour " << c;
    }
  }
  EXPECT_EQ(all.size(), m.springs.size());
  EXPECT_EQ(m.colour_begin.back(), static_cast<int32_t>(m.springs.size()));
}

// Every edge is in exactly one chain or left over; in a layer no particle is in two chains;
// a chain's neighbours are joined by an edge; a chain has at least `min_length` edges.
void expect_cover(const std::vector<Vec3>& x, const std::vector<std::pair<int32_t, int32_t>>& edges,
                  const xpbd::ChainCover& cover, int min_length) {
  std::multiset<std::pair<int32_t, int32_t>> covered;
  std::set<std::pair<int32_t, int32_t>> all;
  for (auto [i, j] : edges) all.insert({std::min(i, j), std::max(i, j)});
  for (const auto& layer : cover.layers) {
    std::vector<int> seen(x.size(), 0);
    for (const std::vector<int32_t>& chain : layer) {
      EXPECT_GE(static_cast<int>(chain.size()) - 1, min_length);
      for (size_t k = 0; k < chain.size(); ++k) {
        EXPECT_EQ(seen[chain[k]]++, 0) << "particle " << chain[k] << " twice in a layer";
        if (k + 1 == chain.size()) continue;
        const std::pair<int32_t, int32_t> e{std::min(chain[k], chain[k + 1]),
                                            std::max(chain[k], chain[k + 1])};
        EXPECT_TRUE(all.count(e)) << "a chain steps off the edges";
        covered.insert(e);
      }
    }
  }
  for (int32_t e : cover.left_over)
    covered.insert({std::min(edges[e].first, edges[e].second),
                    std::max(edges[e].first, edges[e].second)});
  EXPECT_EQ(covered.size(), all.size());
  for (const auto& e : all) EXPECT_EQ(covered.count(e), 1u);
}

TEST(ChainCover, AGridLikeMeshsRowsAndColumnsFillALayerEach) {
  // Without jitter the mesh's rows and columns are straight: each fills one layer, whole.
  const ClothModel m = build_model(bare_mesh(shapes::jittered_grid(1.0, 10, 0.0)).cloth);
  const auto edges = structural_edges(m);
  const xpbd::ChainCover cover = xpbd::cover_with_chains(m.rest_position, edges, 4, 3);
  expect_cover(m.rest_position, edges, cover, 3);
  ASSERT_GE(cover.layers.size(), 2u);
  for (int f = 0; f < 2; ++f) {
    EXPECT_EQ(cover.layers[f].size(), 10u);
    for (const auto& chain : cover.layers[f]) EXPECT_EQ(chain.size(), 10u);
  }
}

TEST(ChainCover, CoversAnIrregularDiscAndAJitteredGrid) {
  for (const ClothMesh& mesh : {shapes::disc(1.0, 8), shapes::jittered_grid(1.0, 12)}) {
    const ClothModel m = build_model(bare_mesh(mesh).cloth);
    const auto edges = structural_edges(m);
    const xpbd::ChainCover cover = xpbd::cover_with_chains(m.rest_position, edges, 4, 3);
    expect_cover(m.rest_position, edges, cover, 3);
    size_t in_chains = 0;
    for (const auto& layer : cover.layers)
      for (const auto& chain : layer) in_chains += chain.size() - 1;
    EXPECT_GT(in_chains, edges.size() / 2);  // most edges are solved as chains
  }
}

// ---- Long-range attachments along the cloth ------------------------------------------------

TEST(Attachments, MeasureTheStraightLineAcrossAFlatCloth) {
  // On a flat cloth the geodesic is the straight line: the unfolding through each triangle
  // keeps the pin as the virtual source, so the limits are the Euclidean distances to
  // round-off, as they were before attachments measured along the cloth.
  for (const bool mesh : {false, true}) {
    SceneDef def = mesh ? bare_mesh(shapes::jittered_grid(2.0, 14)) : SceneDef{};
    if (mesh) {
      def.cloth.pins = {Pin::at_vertex(0), Pin::at_vertex(13), Pin::at_vertex(14 * 14 - 1)};
    } else {
      def.cloth.cols = def.cloth.rows = 14;
      def.cloth.pins = {{0, 0}, {-1, 0}, {-1, -1}};
    }
    def.cloth.long_range.enabled = true;
    const ClothModel m = build_model(def.cloth);
    const ClothState s = initial_state(def.cloth, m);
    LongRange lr;
    lr.prepare(m, s, def.cloth.long_range);
    ASSERT_EQ(lr.tethers(), 3);
    EXPECT_TRUE(lr.uniform());  // three pins: every particle is tethered to all, in order
    for (int32_t p = 0; p < m.size(); ++p)
      for (int t = 0; t < 3; ++t) {
        const double straight = (m.rest_position[p] - m.rest_position[lr.pin(p, t)]).norm();
        EXPECT_NEAR(lr.limit(p, t), straight, 1e-9 * (1.0 + straight)) << p;
      }
  }
}

TEST(Attachments, MeasureAlongATubesSurfaceNotThroughIt) {
  // A tube of radius r: the geodesic from a vertex of its top ring to a point Δθ round and Δy
  // down is the straight line on the tube unrolled, sqrt((r·Δθ)² + Δy²), which for the far
  // side is much longer than the chord through the tube. The mesh's surface is the inscribed
  // polygonal one (its chords shorten the way round by a fraction ~(π/n)²/6), and the
  // unfolding is exact where one source's front crosses the triangles: within an edge length.
  const double r = 0.3, height = 1.0;
  const int around = 32, down = 27;
  SceneDef def = bare_mesh(shapes::tube(r, height, around, down));
  def.cloth.pins = {Pin::at_vertex(0)};
  def.cloth.long_range.enabled = true;
  const ClothModel m = build_model(def.cloth);
  LongRange lr;
  lr.prepare(m, initial_state(def.cloth, m), def.cloth.long_range);
  double edge = 0.0;
  for (const Spring& s : m.springs) edge = std::max(edge, s.rest);
  double worst = 0.0;
  for (int32_t p = 0; p < m.size(); ++p) {
    const Vec3 x = m.rest_position[p];
    double angle = std::abs(std::atan2(x.z(), x.x()));  // from vertex 0 at angle 0
    angle = std::min(angle, 2 * std::numbers::pi - angle);
    const double along = std::hypot(r * angle, x.y() - m.rest_position[0].y());
    worst = std::max(worst, std::abs(lr.limit(p, 0) - along));
    EXPECT_NEAR(lr.limit(p, 0), along, edge) << "vertex " << p;
  }
  EXPECT_LT(worst, edge);
  // The far side of the top ring: half way round, not across.
  const int32_t far = around / 2;
  EXPECT_NEAR(lr.limit(far, 0), std::numbers::pi * r, edge);
  EXPECT_GT(lr.limit(far, 0), 1.4 * 2 * r);
}

TEST(Attachments, ManyPinsTetherEachParticleToItsNearestFour) {
  // A flag pinned along its pole by a box: each particle keeps its four nearest pins.
  SceneDef def = bare_mesh(shapes::flag(1.5, 1.0, 0.3, 16, 11));
  def.cloth.pins = {Pin::in_box(Vec3(-0.01, -2, -1), Vec3(0.01, 1, 1))};
  def.cloth.long_range.enabled = true;
  const ClothModel m = build_model(def.cloth);
  const ClothState s = initial_state(def.cloth, m);
  LongRange lr;
  lr.prepare(m, s, def.cloth.long_range);
  EXPECT_EQ(lr.pins().size(), 11u);
  EXPECT_EQ(lr.tethers(), LongRange::kMaxTethers);
  EXPECT_FALSE(lr.uniform());
  for (int32_t p = 0; p < m.size(); ++p) {
    if (s.pinned[p]) continue;
    // Its tethers are the pins nearest along the flat cloth (straight lines here).
    std::vector<double> d;
    for (int32_t a : lr.pins()) d.push_back((m.rest_position[p] - m.rest_position[a]).norm());
    std::sort(d.begin(), d.end());
    double farthest = 0.0;
    for (int t = 0; t < lr.tethers(); ++t) farthest = std::max(farthest, lr.limit(p, t));
    EXPECT_NEAR(farthest, d[3], 1e-9) << p;
  }
}

// ---- Every method on a mesh --------------------------------------------------------------

class EachMethodOnAMesh : public ::testing::TestWithParam<Variant> {};

TEST_P(EachMethodOnAMesh, FreeFallMatchesItsDiscreteSolution) {
  // As on the grid: from rest every spring stays at rest length and every particle falls as
  // v_n = n·h·g, x_n = x₀ + h²·g·n(n+1)/2, whatever its mass (masses by area differ here).
  // Round-off allowances as for the grid (solvers_test.cpp): 1e-12 relative; fast 1e-10;
  // single precision n·ε.
  SceneDef def = with(bare_mesh(shapes::jittered_grid(1.0, 10)), GetParam());
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  Simulation sim(def);
  const std::vector<Vec3> x0 = sim.state().x;
  const int frames = 60;
  // The discrete solution substep by substep, with each frame's own substeps (auto may change
  // them between frames): v += h·g, x += h·v.
  const double g = 9.81;
  double discrete = 0.0, v = 0.0, n = 0.0;
  for (int f = 0; f < frames; ++f) {
    const int substeps = sim.substeps_per_frame();
    const double h = def.solver.dt / substeps;
    for (int k = 0; k < substeps; ++k) {
      v -= h * g;
      discrete += h * v;
    }
    n += substeps;
    ASSERT_TRUE(sim.step()) << sim.divergence();
  }
  const double ro = single(GetParam())                 ? n * std::numeric_limits<float>::epsilon()
                    : GetParam().method == Method::fast ? 1e-10
                                                        : 1e-12;
  for (int32_t i = 0; i < sim.model().size(); ++i) {
    EXPECT_NEAR(sim.state().x[i].y() - x0[i].y(), discrete, ro * std::abs(discrete));
    EXPECT_NEAR(sim.state().x[i].x(), x0[i].x(), ro);
  }
}

TEST_P(EachMethodOnAMesh, MomentumIsConservedWithNoExternalForces) {
  // Allowances as on the grid (solvers_test.cpp, MomentumIsConservedWithNoExternalForces).
  SceneDef def = with(bare_mesh(shapes::disc(1.0, 6)), GetParam());
  def.cloth.perturbation = 0.2;  // start strained, so the springs work hard
  def.solver.cg_tolerance = 1e-10;
  Simulation sim(def);
  sim.grab(7);
  sim.release(Vec3(1.0, -2.0, 3.0));
  const Vec3 p0 = momentum(sim);
  const int frames = 120;
  const double tolerance = momentum_allowance(GetParam(), frames, sim.substeps_per_frame());
  for (int f = 0; f < frames; ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    EXPECT_LT((momentum(sim) - p0).norm(), tolerance * (1.0 + p0.norm())) << "frame " << f;
  }
}

TEST_P(EachMethodOnAMesh, ADiscDrapedOverASphereComesToRestOutsideIt) {
  // The round tablecloth's case at a small size: a disc of radius 0.8 m dropped on a sphere of
  // radius 0.5 m comes to rest with no particle inside the sphere by more than 1% of its
  // radius (the bench's bar).
  SceneDef def = with(bare_mesh(shapes::disc(0.8, 8)), GetParam());
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.forces.air_drag = 0.002;
  def.cloth.transform.translate = Vec3(0.0, 0.6, 0.0);
  def.cloth.perturbation = 0.01;
  def.colliders.push_back(ColliderDef{});  // a sphere of radius 0.5 at the origin
  // fast damps the whole relative velocity of a spring's ends, so its cloth folds like card
  // at the others' damping and slides off as a stiff cap (README, known traps): a tenth of it.
  if (GetParam().method == Method::fast) {
    def.cloth.structural.damping /= 10;
    def.cloth.bending.damping /= 10;
  }
  Simulation sim(def);
  while (sim.time() < 4.0 - 1e-9) ASSERT_TRUE(sim.step()) << sim.divergence();
  const Diagnostics d = sim.diagnostics();
  EXPECT_LE(d.max_penetration, 0.01 * 0.5);
  EXPECT_LT(d.kinetic_energy, 1e-3);  // at rest
  double lowest = 1.0;
  for (const Vec3& x : sim.state().x) lowest = std::min(lowest, x.y());
  EXPECT_LT(lowest, 0.2);  // draped: its rim hangs well down the sphere
  EXPECT_GT(sim.state().x[0].y(), 0.5);  // its centre sits on top
}

TEST_P(EachMethodOnAMesh, PinsByVertexAndByBoxStayExactlyFixed) {
  // A flag pinned along its pole by a box, and its fly's tip by vertex index.
  SceneDef def = with(bare_mesh(shapes::flag(1.0, 0.6, 0.2, 10, 7)), GetParam());
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.cloth.long_range.enabled = GetParam().line_passes > 0;  // line passes need them pinned
  def.cloth.pins = {Pin::in_box(Vec3(-0.01, -1, -1), Vec3(0.01, 1, 1)), Pin::at_vertex(9)};
  Simulation sim(def);
  const std::vector<Vec3> x0 = sim.state().x;
  int pinned = 0;
  for (int32_t i = 0; i < sim.model().size(); ++i) pinned += sim.state().pinned[i];
  EXPECT_EQ(pinned, 7 + 1);  // the pole's seven and the tip
  EXPECT_TRUE(sim.state().pinned[9]);
  for (int f = 0; f < 60; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  double moved = 0.0;
  for (int32_t i = 0; i < sim.model().size(); ++i) {
    if (sim.state().pinned[i]) EXPECT_EQ(sim.state().x[i], x0[i]) << i;  // exactly
    else moved = std::max(moved, (sim.state().x[i] - x0[i]).norm());
  }
  EXPECT_GT(moved, 1e-3);  // the rest sags
  EXPECT_EQ(sim.diagnostics().pinned_drift, 0.0);
}

TEST_P(EachMethodOnAMesh, SameBitsTwiceAndOnOneThreadOrTwo) {
  // An irregular mesh large enough that loops take threads, dropped on a sphere; heavy, so that
  // the automatic substeps are few and the test stays quick (as
  // Determinism.TheThreadCountDoesNotChangeTheBits does on the grid).
  SceneDef def = with(bare_mesh(shapes::jittered_grid(2.0, 91)), GetParam());
  ASSERT_GE(particle_count(def.cloth), kParallelMin);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.cloth.mass = 100.0;
  if (GetParam().method != Method::automatic) def.solver.stiff_sweeps = 2;
  def.cloth.perturbation = 0.01;
  def.colliders.push_back(ColliderDef{.center = Vec3(0.0, -0.49, 0.0)});
  auto run = [&](int threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    Simulation sim(def);
    for (int f = 0; f < 3; ++f) EXPECT_TRUE(sim.step()) << sim.divergence();
    return sim.state().x;
  };
  const int threads = max_threads();
  const std::vector<Vec3> one = run(1), two = run(2), again = run(2);
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  ASSERT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(Vec3)), 0);
  ASSERT_EQ(std::memcmp(two.data(), again.data(), two.size() * sizeof(Vec3)), 0);
}

TEST_P(EachMethodOnAMesh, SameBitsTwiceWithSpringsOnlyOneThreadCanSweep) {
  // A disc whose centre has valence 100: the springs past the 63 independent colours are swept
  // by one thread, in order, so twice gives the same bits.
  SceneDef def = with(bare_mesh(shapes::disc(1.0, 4, 100)), GetParam());
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.cloth.perturbation = 0.05;
  def.cloth.mass = 20.0;  // heavy, so that symplectic's substeps stay few round the fan
  def.colliders.push_back(ColliderDef{.center = Vec3(0.0, -0.6, 0.0)});
  auto run = [&] {
    Simulation sim(def);
    for (int f = 0; f < 30; ++f) EXPECT_TRUE(sim.step()) << sim.divergence();
    return sim.state().x;
  };
  const std::vector<Vec3> a = run(), b = run();
  ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)), 0);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, EachMethodOnAMesh, ::testing::ValuesIn(kVariants),
                         variant_name);

TEST(MeshStaticEquilibrium, FourCornerSagMatchesSymplecticWithEveryMethod) {
  // A square mesh (irregular triangles) pinned by vertex at its four corners sags to rest, and
  // every method finds the same rest shape as the symplectic reference within 5% of the sag, as
  // on the grid (solvers_test.cpp: xpbd at 200 substeps, its one sweep per substep converging
  // slowly across the cloth).
  const int n = 12;
  SceneDef def = bare_mesh(shapes::jittered_grid(2.0, n, 0.2));
  def.cloth.transform.translate = Vec3(0.0, 1.0, 0.0);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.forces.air_drag = ForcesDef().air_drag;  // as the grid's test, which keeps the default
  def.cloth.pins = {Pin::at_vertex(0), Pin::at_vertex(n - 1), Pin::at_vertex(n * (n - 1)),
                    Pin::at_vertex(n * n - 1)};
  def.cloth.structural.damping = def.cloth.bending.damping = 2.0;  // settles within 12 s
  testing_support::expect_every_method_rests_where_symplectic_does(def);
}

// ---- What a mesh must be -------------------------------------------------------------------

struct BadMesh {
  const char* what;
  ClothMesh mesh;
  const char* words;
};

void PrintTo(const BadMesh& b, std::ostream* os) { *os << b.what; }

class MeshCheck : public ::testing::TestWithParam<BadMesh> {};

TEST_P(MeshCheck, IsRefusedNamingTheProblem) {
  SceneDef def = bare_mesh(GetParam().mesh);
  try {
    Simulation sim(def);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "cloth.mesh");
    EXPECT_NE(std::string(e.what()).find(GetParam().words), std::string::npos) << e.what();
  }
}

ClothMesh square() {
  ClothMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

ClothMesh changed(ClothMesh m, const std::function<void(ClothMesh&)>& change) {
  change(m);
  return m;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MeshCheck,
    ::testing::Values(
        BadMesh{"no triangles", changed(square(), [](ClothMesh& m) { m.triangles.clear(); }),
                "has no triangles"},
        BadMesh{"index out of range",
                changed(square(), [](ClothMesh& m) { m.triangles[1][2] = 7; }),
                "triangle 1 names vertex 7, but there are 4 vertices"},
        BadMesh{"non-finite", changed(square(), [](ClothMesh& m) { m.positions[2].x() = NAN; }),
                "vertex 2 has a coordinate that is not a finite number"},
        BadMesh{"zero area",
                changed(square(), [](ClothMesh& m) { m.positions[2] = Vec3(2, 0, 0); }),
                "triangle 0 (vertices 0, 1, 2) has zero area"},
        BadMesh{"repeated corner",
                changed(square(), [](ClothMesh& m) { m.triangles[0] = {0, 1, 1}; }),
                "has zero area"},
        BadMesh{"unused vertex",
                changed(square(), [](ClothMesh& m) { m.positions.push_back(Vec3(5, 5, 5)); }),
                "vertex 4 belongs to no triangle"},
        BadMesh{"non-manifold",
                changed(square(),
                        [](ClothMesh& m) {
                          m.positions.push_back(Vec3(0.5, 0.5, 1));
                          m.triangles.push_back({0, 2, 4});
                        }),
                "the edge between vertices 0 and 2 is shared by 3 triangles"}));

TEST(MeshPins, GridFormsAreRefusedOnAMeshAndAnEmptyBoxNamesTheCloth) {
  SceneDef def = bare_mesh(square());
  def.cloth.pins = {{0, 0}};
  try {
    Simulation sim(def);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "cloth.pins[0]");
    EXPECT_NE(std::string(e.what()).find("needs a grid cloth"), std::string::npos);
  }
  def.cloth.pins = {Pin::at_vertex(3), Pin::in_box(Vec3(5, 5, 5), Vec3(6, 6, 6))};
  try {
    Simulation sim(def);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "cloth.pins[1].box");
    EXPECT_NE(std::string(e.what()).find("holds no vertex"), std::string::npos) << e.what();
  }
  def.cloth.pins = {Pin::at_vertex(4)};
  EXPECT_THROW(Simulation{def}, InputError);
}

}  // namespace
}  // namespace drape
