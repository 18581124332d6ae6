// The large-step methods (implicit, xpbd, fast) and long-range attachments: their constraint
// math on its own, then whole simulations against closed forms, conservation laws, the
// symplectic reference and the stability and strain promises. Tolerances are stated
// next to each check with their reason.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <utility>

#include "drape/error.h"
#include "drape/material.h"
#include "drape/mesh.h"
#include "drape/simulation.h"
#include "equilibrium.h"
#include "forces.h"
#include "io/scene_io.h"
#include "long_range.h"
#include "model/model.h"
#include "solvers/solver.h"
#include "solvers/system_factor.h"
#include "solvers/xpbd/constraints.h"
#include "test_scenes.h"
#include "variants.h"

namespace drape {
namespace {

using testing_support::bare;
using testing_support::bench_scene;
using testing_support::kVariants;
using testing_support::momentum;
using testing_support::momentum_allowance;
using testing_support::shipped;
using testing_support::single;
using testing_support::Variant;
using testing_support::variant_name;
using testing_support::with;

Vec3 random_vec(int seed) {
  return Vec3(std::sin(1.3 * seed + 0.1), std::cos(2.1 * seed + 0.7), std::sin(0.7 * seed + 2.0));
}

// ---- Constraint math on its own -------------------------------------------------------------

TEST(XpbdDistance, ZeroComplianceSatisfiesTheConstraintAndConservesMomentum) {
  for (int seed = 1; seed <= 10; ++seed) {
    const Vec3 xi = random_vec(seed), xj = random_vec(seed + 50);
    const double mi = 0.5 + 0.1 * seed, mj = 2.0 - 0.1 * seed, rest = 0.2 + 0.05 * seed;
    const DistanceCorrection d =
        xpbd_distance(xi, 1.0 / mi, xj, 1.0 / mj, rest, 0.0, 0.0, Vec3::Zero(), Vec3::Zero(), 0.0);
    // One projection of a single rigid constraint meets it exactly (up to round-off).
    EXPECT_NEAR(((xj + d.dxj) - (xi + d.dxi)).norm(), rest, 1e-14);
    // Corrections weighted by inverse mass: m_i·Δx_i + m_j·Δx_j = 0 (no momentum change).
    EXPECT_LT((mi * d.dxi + mj * d.dxj).norm(), 1e-14);
  }
}

TEST(XpbdDistance, ComplianceGivesTheClosedFormCorrection) {
  // One spring, one particle free (w_i = 0): Δλ = −C/(w_j + α̃), so the stretch left after the
  // step is C·α̃/(w_j + α̃) — the backward-Euler balance of k·stretch with the inertia m/h².
  const Vec3 xi(0.0, 0.0, 0.0), xj(1.5, 0.0, 0.0);
  const double k = 100.0, h = 0.01, m = 0.02, rest = 1.0;
  const double alpha_tilde = 1.0 / (k * h * h);
  const DistanceCorrection d =
      xpbd_distance(xi, 0.0, xj, 1.0 / m, rest, alpha_tilde, 0.0, Vec3::Zero(), Vec3::Zero(), 0.0);
  const double c = 0.5;
  const double left = c * alpha_tilde / (1.0 / m + alpha_tilde);
  EXPECT_EQ(d.dxi, Vec3::Zero());
  EXPECT_NEAR((xj + d.dxj).x() - rest, left, 1e-14);
  EXPECT_NEAR(d.dlambda, -c / (1.0 / m + alpha_tilde), 1e-14);
}

TEST(XpbdDistance, DampingResistsTheRelativeMotionAlongTheSpring) {
  // At rest length (C = 0) only damping acts: ends separating along the spring are pulled
  // back together, by more as γ grows, and never past their previous separation.
  const Vec3 xi(0.0, 0.0, 0.0), xj(1.0, 0.0, 0.0), moved_j(0.1, 0.0, 0.0);
  double last = 0.0;
  for (double gamma : {0.5, 2.0, 8.0}) {
    const DistanceCorrection d =
        xpbd_distance(xi, 1.0, xj, 1.0, 1.0, 1.0, gamma, Vec3::Zero(), moved_j, 0.0);
    EXPECT_LT(d.dxj.x(), 0.0);
    EXPECT_GT(d.dxi.x(), 0.0);
    EXPECT_GT(-d.dxj.x(), last);
    EXPECT_LT(-d.dxj.x() - d.dxi.x(), moved_j.x());
    last = -d.dxj.x();
  }
}

TEST(XpbdDistance, ACompressedSoftenedSpringActsWithTheCompressionsStiffness) {
  // Compressed, a spring softened by c acts as one of stiffness c·k: compliance α̃/c, damping
  // γ/c. Stretched, softening changes nothing. With c = 0 and no damping it does not act.
  const Vec3 xi(0.0, 0.0, 0.0), moved_j(0.02, 0.01, 0.0);
  const double alpha = 3.0, gamma = 0.4, c = 0.1;
  for (double length : {0.8, 1.3}) {
    const Vec3 xj(length, 0.1, 0.0);
    const DistanceCorrection soft =
        xpbd_distance(xi, 1.0, xj, 2.0, 1.0, alpha, gamma, Vec3::Zero(), moved_j, 0.0, c);
    const double f = length < 1.0 ? c : 1.0;
    const DistanceCorrection as_k =
        xpbd_distance(xi, 1.0, xj, 2.0, 1.0, alpha / f, gamma / f, Vec3::Zero(), moved_j, 0.0);
    EXPECT_NEAR((soft.dxj - as_k.dxj).norm(), 0.0, 1e-15) << length;
    EXPECT_NEAR((soft.dxi - as_k.dxi).norm(), 0.0, 1e-15) << length;
  }
  const DistanceCorrection none = xpbd_distance(xi, 1.0, Vec3(0.5, 0.0, 0.0), 2.0, 1.0, alpha, 0.0,
                                                Vec3::Zero(), Vec3::Zero(), 0.0, 0.0);
  EXPECT_EQ(none.dxj, Vec3::Zero());
  EXPECT_EQ(none.dxi, Vec3::Zero());
}

// xpbd_bend on four corners given as vectors: their moves.
std::array<Vec3, 4> bend_moves(const std::array<Vec3, 4>& x, const std::array<double, 4>& inv_mass,
                               const std::array<double, 4>& weight, double alpha_tilde) {
  double bx[4], by[4], bz[4], mx[4] = {}, my[4] = {}, mz[4] = {};
  for (int k = 0; k < 4; ++k) bx[k] = x[k].x(), by[k] = x[k].y(), bz[k] = x[k].z();
  const int32_t v[4] = {0, 1, 2, 3};
  double lambda[3] = {0.0, 0.0, 0.0};
  xpbd_bend(bx, by, bz, mx, my, mz, inv_mass.data(), v, weight.data(), alpha_tilde, lambda);
  std::array<Vec3, 4> d;
  for (int k = 0; k < 4; ++k) d[k] = Vec3(mx[k], my[k], mz[k]);
  return d;
}

const std::array<Vec3, 4> kBendCorners = {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0),
                                          Vec3(0.5, 0.2, 0.8), Vec3(0.4, -0.1, -0.9)};
const std::array<double, 4> kBendWeights = {-1.1, -0.9, 1.2, 0.8},
                            kBendInvMass = {2.0, 1.0, 0.5, 4.0};

TEST(XpbdBend, OneProjectionGivesTheClosedFormAndConservesMomentum) {
  // The curvature vector C = Σ w_k·x_k is linear in x, so one projection of a rigid element
  // flattens it exactly, and a compliant one leaves C·α̃/(W + α̃), W = Σ w_k²/m_k, as a
  // spring's does; Σ w_k = 0 makes the moves momentum-free.
  Vec3 c = Vec3::Zero();
  double W = 0.0;
  for (int k = 0; k < 4; ++k)
    c += kBendWeights[k] * kBendCorners[k],
        W += kBendWeights[k] * kBendWeights[k] * kBendInvMass[k];
  for (double alpha : {0.0, 0.7}) {
    const std::array<Vec3, 4> d = bend_moves(kBendCorners, kBendInvMass, kBendWeights, alpha);
    Vec3 after = Vec3::Zero(), momentum = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      after += kBendWeights[k] * (kBendCorners[k] + d[k]), momentum += d[k] / kBendInvMass[k];
    EXPECT_NEAR((after - c * alpha / (W + alpha)).norm(), 0.0, 1e-14) << alpha;
    EXPECT_NEAR(momentum.norm(), 0.0, 1e-14) << alpha;
  }
}

TEST(XpbdDamping, TakesTheRelativeRateToItsBackwardEulerValueAndKeepsMomentum) {
  // A spring (a material's bending is damped apart: BendingDamping in material_test.cpp): the ends'
  // relative speed along it, u, becomes u/(1 + h·c·(wi + wj)); across it nothing changes.
  const double h = 0.01, c = 3.0, wi = 2.0, wj = 0.5;
  double bx[2] = {0.0, 0.6}, by[2] = {0.0, 0.8}, bz[2] = {0.0, 0.0}, m0[2] = {0.0, 0.0};
  double vx[2] = {0.3, -1.0}, vy[2] = {0.1, 2.0}, vz[2] = {0.0, 1.5}, w[2] = {wi, wj};
  const Vec3 d(0.6, 0.8, 0.0);
  auto relative = [&] { return Vec3(vx[1] - vx[0], vy[1] - vy[0], vz[1] - vz[0]); };
  auto momentum = [&] {
    return Vec3(vx[0] / wi + vx[1] / wj, vy[0] / wi + vy[1] / wj, vz[0] / wi + vz[1] / wj);
  };
  const Vec3 r0 = relative(), p0 = momentum();
  damp_spring(bx, by, bz, m0, m0, m0, vx, vy, vz, w, 0, 1, h * c);
  const Vec3 r1 = relative();
  EXPECT_NEAR(r1.dot(d), r0.dot(d) / (1.0 + h * c * (wi + wj)), 1e-15);
  EXPECT_NEAR((r1 - r1.dot(d) * d - (r0 - r0.dot(d) * d)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((momentum() - p0).norm(), 0.0, 1e-14);
}

TEST(LongRangeConstraint, ProjectsOntoTheLimitAndRemovesOnlyOutwardVelocity) {
  const Vec3 anchor(1.0, 2.0, 3.0);
  Vec3 x = anchor + Vec3(3.0, 4.0, 0.0);  // 5 m away
  const Vec3 u = project_attachment(anchor, 2.0, x);
  EXPECT_NEAR((x - anchor).norm(), 2.0, 1e-15);
  EXPECT_NEAR((u - Vec3(0.6, 0.8, 0.0)).norm(), 0.0, 1e-15);
  Vec3 v(1.0, 1.0, 1.0);  // outward along u by 1.4
  clamp_outward_velocity(u, v);
  EXPECT_NEAR(v.dot(u), 0.0, 1e-15);
  EXPECT_NEAR(v.z(), 1.0, 1e-15);  // the tangential part is untouched
  Vec3 inward = -u;                // moving back toward the pin: kept
  clamp_outward_velocity(u, inward);
  EXPECT_EQ(inward, -u);
  Vec3 inside = anchor + Vec3(0.5, 0.0, 0.0);  // within the limit: unconstrained
  EXPECT_EQ(project_attachment(anchor, 2.0, inside), Vec3::Zero());
  EXPECT_EQ(inside, anchor + Vec3(0.5, 0.0, 0.0));
}

TEST(ImplicitStep, SpringBlockMatchesFiniteDifferencesOfTheForcesOnStretchedSprings) {
  // The Newton matrix block of a spring must be −(h²·∂f_i/∂x_i + h·∂f_i/∂v_i): checked column
  // by column against central differences of the elastic and damping forces (step 1e-6,
  // error O(eps²)·|f'''| ≈ 1e-10 relative). Stretched springs only: the clamp changes
  // compressed ones on purpose.
  const double eps = 1e-6, h = 1.0 / 60.0;
  for (int seed = 1; seed <= 10; ++seed) {
    const Vec3 xi = random_vec(seed), vi = random_vec(seed + 7), vj = random_vec(seed + 9);
    const Vec3 dir = random_vec(seed + 100).normalized();
    const double k = 500.0 + 10 * seed, c = 0.3 + 0.1 * seed, rest = 0.5;
    const Vec3 xj = xi + (rest * (1.05 + 0.05 * seed)) * dir;  // 10% to 55% stretched
    const Mat3 block = forces::implicit_spring_block(xi, xj, k, rest, c, h);
    for (int a = 0; a < 3; ++a) {
      Vec3 xp = xi, xm = xi, vp = vi, vm = vi;
      xp[a] += eps;
      xm[a] -= eps;
      vp[a] += eps;
      vm[a] -= eps;
      const Vec3 dfdx =
          (forces::spring_elastic(xp, xj, k, rest) - forces::spring_elastic(xm, xj, k, rest)) /
          (2 * eps);
      const Vec3 dfdv =
          (forces::spring_damping(xi, xj, vp, vj, c) - forces::spring_damping(xi, xj, vm, vj, c)) /
          (2 * eps);
      const Vec3 expected = -(h * h * dfdx + h * dfdv);
      EXPECT_LT((block.col(a) - expected).norm(), 1e-7 * (1.0 + expected.norm()))
          << "seed " << seed << " column " << a;
    }
  }
}

TEST(ImplicitStep, SpringBlockOfACompressedSpringStaysPositiveSemiDefinite) {
  const Vec3 xi(0.0, 0.0, 0.0), xj(0.3, 0.2, 0.1);  // length 0.37 < rest 1: compressed
  const Mat3 block = forces::implicit_spring_block(xi, xj, 1000.0, 1.0, 0.5, 1.0 / 60.0);
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(block);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12);
}

// The factor `implicit` preconditions with where block-Jacobi is slow: applied to a residual r
// it must give the z that solves the filtered system, S·A·z = S·r with z in S's range, A
// assembled here densely from its definition (M, each spring's block ±B, each bending element's
// (h²k + h·d)·w_a·w_b·I), on a perturbed irregular mesh with every kind of filter: free,
// a contact plane, two contacts (a line), pinned.
TEST(ImplicitStep, SystemFactorSolvesTheFilteredSystemOnEveryKindOfParticle) {
  ClothDef def;
  def.material = material_preset("denim");
  def.mesh = std::make_shared<ClothMesh>(shapes::jittered_grid(0.5, 5, 0.3, 3));
  def.pins.clear();
  const ClothModel m = build_model(def);
  const int32_t n = m.size();
  const double h = 1.0 / 60.0;
  std::vector<Vec3> x = m.rest_position;
  for (int32_t p = 0; p < n; ++p)  // stretched and compressed springs, bent elements
    x[p] += 0.01 * Vec3(std::sin(1.7 * p), std::cos(0.9 * p + 0.4), std::sin(2.3 * p + 1.1));
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int32_t p = 0; p < n; ++p) A.block<3, 3>(3 * p, 3 * p) += m.mass[p] * Mat3::Identity();
  std::vector<Mat3> blocks;
  for (const Spring& sp : m.springs) {
    const Mat3 B =
        forces::implicit_spring_block(x[sp.i], x[sp.j], sp.stiffness, sp.rest, sp.damping, h);
    blocks.push_back(B);
    A.block<3, 3>(3 * sp.i, 3 * sp.i) += B;
    A.block<3, 3>(3 * sp.j, 3 * sp.j) += B;
    A.block<3, 3>(3 * sp.i, 3 * sp.j) -= B;
    A.block<3, 3>(3 * sp.j, 3 * sp.i) -= B;
  }
  for (const BendingElement& b : m.bending)
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l)
        A.block<3, 3>(3 * b.v[k], 3 * b.v[l]) +=
            (h * h * b.stiffness + h * b.damping) * b.w[k] * b.w[l] * Mat3::Identity();
  std::vector<Mat3> diag(n), filter(n, Mat3::Identity());
  for (int32_t p = 0; p < n; ++p) diag[p] = A.block<3, 3>(3 * p, 3 * p);
  const Vec3 e1 = Vec3(1.0, 2.0, -0.5).normalized(), e2 = Vec3(2.0, -1.0, 0.0).normalized();
  for (int32_t p = 0; p < n; ++p)  // one contact or two
    if (p % 7 == 1)
      filter[p] -= e1 * e1.transpose() + e2 * e2.transpose();
    else if (p % 3 == 0)
      filter[p] -= e1 * e1.transpose();
  filter[2].setZero();  // pinned
  filter[n - 1].setZero();

  SystemFactor factor;
  factor.prepare(m);
  EXPECT_FALSE(factor.ready());
  EXPECT_GT(factor.entries(), 6 * n);  // L holds at least the diagonal blocks' lower parts
  ASSERT_TRUE(factor.factorise(m, diag, blocks, h, filter));
  std::vector<Vec3> r(n), z(n);
  for (int32_t p = 0; p < n; ++p) r[p] = Vec3(std::cos(3.1 * p), std::sin(0.3 * p), 1.0);
  factor.apply(r, filter, z);
  Eigen::VectorXd zv(3 * n);
  for (int32_t p = 0; p < n; ++p) zv.segment<3>(3 * p) = z[p];
  const Eigen::VectorXd Az = A * zv;
  double r_max = 0.0;
  for (int32_t p = 0; p < n; ++p) r_max = std::max(r_max, (filter[p] * r[p]).norm());
  for (int32_t p = 0; p < n; ++p) {
    EXPECT_LT(((Mat3::Identity() - filter[p]) * z[p]).norm(), 1e-14) << "particle " << p;
    EXPECT_LT((filter[p] * (Vec3(Az.segment<3>(3 * p)) - r[p])).norm(), 1e-10 * r_max)
        << "particle " << p;
  }
}

// ---- Every new method -----------------------------------------------------------------------

class EachMethod : public ::testing::TestWithParam<Variant> {};

// The free fall from rest of FreeFallMatchesItsDiscreteSolutionAndTheClosedForm.
void expect_free_fall(const SceneDef& def, const Variant& v) {
  Simulation sim(def);
  const std::vector<Vec3> x0 = sim.state().x;
  const int frames = 60;
  for (int f = 0; f < frames; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const double h = def.solver.dt / sim.substeps_per_frame();
  const double n = frames * sim.substeps_per_frame(), t = n * h, g = 9.81;
  const double discrete = -h * h * g * n * (n + 1) / 2;
  const double closed = -0.5 * g * t * t;
  const double ro = single(v)                  ? n * std::numeric_limits<float>::epsilon()
                    : v.method == Method::fast ? 1e-10
                                               : 1e-12;
  for (int32_t i = 0; i < sim.model().size(); ++i) {
    const double drop = sim.state().x[i].y() - x0[i].y();
    EXPECT_NEAR(drop, discrete, ro * std::abs(discrete));
    // First order: ½ghT, plus the round-off.
    EXPECT_LE(std::abs(drop - closed), 0.5 * g * h * t * (1 + 1e-9) + ro * std::abs(discrete));
    EXPECT_NEAR(sim.state().v[i].y(), -g * t, ro * g * t);
    EXPECT_NEAR(sim.state().x[i].x(), x0[i].x(), ro);  // and straight down
  }
}

TEST_P(EachMethod, FreeFallMatchesItsDiscreteSolutionAndTheClosedForm) {
  // Each method's discrete free fall from rest is v_n = n·h·g, x_n = x₀ + h²·g·n(n+1)/2:
  // implicit's Newton step starts from Δv = h·g and its residual is then zero; xpbd's
  // springs stay at rest length; fast's first global step lands on y. Round-off allowance
  // 1e-12 relative (hundreds of additions of a few ulps each); for fast 1e-10, since its
  // positions come out of a sparse Cholesky solve whose error, about κ·ε per step with
  // κ ≈ 1 + 8h²k/m ≈ 300 here, is divided by h to make the velocity. In single precision each
  // of the n substeps rounds the velocity and the move to float (positions are kept as base +
  // move, so the base's rounding is carried, not lost): allowance n·ε relative, ε = 2^-23.
  // The same with a collider far below, out of reach over the whole fall: a method's contact
  // handling must not slow a cloth that touches nothing (fast's contact term once did, to a
  // crawl). Line passes find every spring at rest length, so they change nothing.
  for (const bool collider : {false, true}) {
    SCOPED_TRACE(collider ? "a sphere far below" : "no collider");
    SceneDef def = with(bare(), GetParam());
    def.forces.gravity = Vec3(0.0, -9.81, 0.0);
    if (collider) def.colliders.push_back(ColliderDef{.center = Vec3(0.0, -100.0, 0.0)});
    expect_free_fall(def, GetParam());
  }
}

TEST_P(EachMethod, MomentumIsConservedWithNoExternalForces) {
  // Every spring force, damping, constraint correction and global-step row pairs equal and
  // opposite, so momentum is exact up to round-off — except the implicit method's CG, whose
  // residual r = b − A·Δv sums to the momentum error: with cg_tolerance 1e-10 that is below
  // 1e-8 of the momentum scale per run — and fast, whose global solve's round-off (κ·ε per
  // step, divided by h, ~2e-12 per frame here) adds up to 1e-9 over the run — and xpbd in
  // single precision, whose velocities are rounded to float (ε = 2^-23 relative) once per
  // substep: allowance n·ε of the momentum scale over the n substeps of the run.
  SceneDef def = with(bare(), GetParam());
  def.cloth.perturbation = 0.02;  // start strained, so the springs work hard
  def.solver.cg_tolerance = 1e-10;
  Simulation sim(def);
  sim.grab(5);
  sim.release(Vec3(1.0, -2.0, 3.0));  // a kick: the cloth now moves and tumbles
  const Vec3 p0 = momentum(sim);
  ASSERT_GT(p0.norm(), 0.01);
  const int frames = 120;
  const double tolerance = momentum_allowance(GetParam(), frames, sim.substeps_per_frame());
  for (int f = 0; f < frames; ++f) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    EXPECT_LT((momentum(sim) - p0).norm(), tolerance * (1.0 + p0.norm())) << "frame " << f;
  }
}

TEST_P(EachMethod, SameSceneTwiceGivesBitIdenticalState) {
  SceneDef def = with(shipped("sphere"), GetParam());
  def.cloth.cols = def.cloth.rows = 16;
  Simulation a(def), b(def);
  for (int f = 0; f < 90; ++f) {
    ASSERT_TRUE(a.step()) << a.divergence();
    ASSERT_TRUE(b.step());
  }
  ASSERT_EQ(std::memcmp(a.state().x.data(), b.state().x.data(), a.state().x.size() * sizeof(Vec3)),
            0);
  ASSERT_EQ(std::memcmp(a.state().v.data(), b.state().v.data(), a.state().v.size() * sizeof(Vec3)),
            0);
}

TEST_P(EachMethod, AFrameSteppedInPartsTakesTheFramesSubstepsInAll) {
  // Self-collision steps a fast-deforming frame in parts (Simulation::step_with_self_collision).
  // Each part takes its share of the frame's substeps: four parts run the same eight substeps
  // as the whole frame and end where it ends. Before, each part ran all eight, a quarter as
  // long (a frame in eight parts cost eight frames), and a free fall of one frame ended
  // g·dt²·(1/2 − 1/8)/8 = 1.3e-4 m higher. auto takes its own substeps (6 here), shared by
  // as many parts as divide them. With line passes every part runs all of them (the passes
  // undo the stretch the collision steps leave; solvers/xpbd): four parts of eight end where a
  // whole frame of 32 ends. fast takes frames whole (its matrix is factorised for the frame's
  // step), and says so.
  SceneDef def = with(bare(), GetParam());
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  def.cloth.perturbation = 0.02;  // strained, so the springs work too
  const bool lines = GetParam().line_passes > 0;
  // Line passes run on a pinned grid only with long-range attachments: this one falls free.
  if (!lines) def.cloth.pins = {{0, 0}, {7, 0}};
  def.solver.substeps = 8;
  const ClothModel model = build_model(def.cloth);
  const std::vector<Collider> colliders;
  int per_frame = 0;
  auto stepped = [&](int parts, int substeps) {
    ClothState state = initial_state(def.cloth, model);
    LongRange attachments;
    attachments.prepare(model, state, def.cloth.long_range);
    World world{model, state, def.forces, colliders, 0.0, attachments};
    SolverDef solver_def = def.solver;
    solver_def.substeps = substeps;
    const std::unique_ptr<Solver> solver = make_solver(solver_def, model);
    solver->prepare(world, solver_def);
    per_frame = solver->substeps();
    EXPECT_EQ(solver->steps_any_dt(), GetParam().method != Method::fast);
    for (int part = 0; part < parts; ++part) {
      world.time = def.solver.dt * part / parts;
      solver->step_frame(world, def.solver.dt / parts);
    }
    return state.x;
  };
  if (GetParam().method == Method::fast) {
    stepped(1, 8);  // checks only that it takes frames whole
    return;
  }
  const std::vector<Vec3> whole = stepped(1, lines ? 32 : 8);
  if (GetParam().method != Method::automatic) {
    ASSERT_EQ(per_frame, lines ? 32 : 8);
  }
  const int parts = lines ? 4 : per_frame % 4 == 0 ? 4 : per_frame % 3 == 0 ? 3 : 2;
  ASSERT_EQ(per_frame % parts, 0) << per_frame;
  const std::vector<Vec3> parted = stepped(parts, 8);
  const double fall = 0.5 * 9.81 * def.solver.dt * def.solver.dt;
  const double ro = single(GetParam()) ? 1e-5 : 1e-12;
  for (size_t i = 0; i < whole.size(); ++i)
    EXPECT_LT((parted[i] - whole[i]).norm(), ro * fall) << "particle " << i;
}

TEST_P(EachMethod, AttachmentsFarFromTheirLimitsChangeNothing) {
  // Long-range limits are unilateral: with slack 1 (twice the rest distance) no particle of a
  // hanging cloth comes near one in its first half second, so the cloth must move exactly as
  // without them. (fast's contact term once sat on every particle when attachments were on,
  // which held the whole cloth back.) Line passes run on a pinned cloth only with attachments,
  // so for them the cloth without attachments is one whose limits are further still (slack 3):
  // neither set may act. So for auto, which chooses line passes only where they may run.
  SceneDef def = with(shipped("hang"), GetParam());
  def.cloth.cols = def.cloth.rows = 16;
  if (GetParam().line_passes > 0 || GetParam().method == Method::automatic)
    def.cloth.long_range = {true, 3.0};
  Simulation plain(def);
  def.cloth.long_range = {true, 1.0};
  Simulation attached(def);
  for (int f = 0; f < 30; ++f) {
    ASSERT_TRUE(plain.step()) << plain.divergence();
    ASSERT_TRUE(attached.step()) << attached.divergence();
  }
  double moved = 0.0;
  for (int32_t i = 0; i < plain.model().size(); ++i) {
    EXPECT_EQ(attached.state().x[i], plain.state().x[i]) << "particle " << i;
    moved = std::max(moved, (plain.state().x[i] - plain.model().rest_position[i]).norm());
  }
  EXPECT_GT(moved, 1e-3);  // the cloth did move: the comparison means something
}

TEST_P(EachMethod, PinsAndTheHandUpdateWhatDependsOnThemAtOnce) {
  // Pinning, dragging and releasing change which particles are free: the factorisation
  // (fast), the filter (implicit) and the attachments must follow at once.
  SceneDef def = with(shipped("hang"), GetParam());
  def.cloth.cols = def.cloth.rows = 12;
  def.cloth.long_range.enabled = true;
  Simulation sim(def);
  for (int f = 0; f < 30; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const int32_t p = sim.model().index(6, 11);
  sim.set_pinned(p, true);
  const Vec3 held = sim.state().x[p];
  for (int f = 0; f < 30; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  EXPECT_EQ(sim.state().x[p], held);  // exactly: a pinned particle never moves
  sim.set_pinned(p, false);
  const int32_t q = sim.model().index(3, 8);
  sim.grab(q);
  const Vec3 target = sim.state().x[q] + Vec3(0.0, 0.0, 0.3);
  sim.move_grab(target);
  for (int f = 0; f < 30; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  EXPECT_EQ(sim.state().x[q], target);  // the hand holds it exactly
  sim.release();
  for (int f = 0; f < 30; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  EXPECT_NE(sim.state().x[q], target);  // free again: it falls back
  EXPECT_EQ(sim.diagnostics().pinned_drift, 0.0);
}

TEST_P(EachMethod, SeesTheHandMoveWhileItHoldsAsIfPreparedAgain) {
  // Moving a held particle prepares nothing again, but the method must start its next frame
  // from the hand's new place (xpbd keeps the state in arrays of its own from frame to frame),
  // as it does once prepared again: reconfigure with the same scene prepares the method and
  // changes nothing else. To the bit. No pins: the cloth hangs from the hand alone, which
  // line passes (that need attachments where pinned) run with too.
  SceneDef def = with(shipped("hang"), GetParam());
  def.cloth.cols = def.cloth.rows = 12;
  def.cloth.pins.clear();
  Simulation held(def), prepared(def);
  const int32_t q = held.model().index(3, 8);
  for (Simulation* sim : {&held, &prepared}) {
    sim->grab(q);
    sim->move_grab(sim->state().x[q] + Vec3(0.0, 0.0, 0.3));
    for (int f = 0; f < 10; ++f) ASSERT_TRUE(sim->step()) << sim->divergence();
  }
  const Vec3 before = held.state().x[q - 1];  // the neighbour the hand pulls
  for (Simulation* sim : {&held, &prepared}) sim->move_grab(sim->state().x[q] + Vec3(0.3, 0, 0));
  prepared.reconfigure(prepared.def());
  for (Simulation* sim : {&held, &prepared})
    for (int f = 0; f < 10; ++f) ASSERT_TRUE(sim->step()) << sim->divergence();
  for (int32_t i = 0; i < held.model().size(); ++i)
    ASSERT_EQ(held.state().x[i], prepared.state().x[i]) << "particle " << i;
  EXPECT_GT((held.state().x[q - 1] - before).x(), 0.1);  // it followed the hand
}

TEST_P(EachMethod, MemoryReportCoversItsArraysGrowsLinearlyAndStaysUnderTheEstimate) {
  // What memory() reports must cover the arrays each part is known to hold, grow linearly with
  // the cloth (fast: its factor's fill grows like n log n on a grid), and stay under the
  // estimate that budgets are checked against before anything is built, without being far
  // from it.
  const Variant v = GetParam();
  double per_particle[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    SceneDef def = with(shipped("hang"), v);
    def.cloth.cols = def.cloth.rows = 32 << k;
    def.cloth.long_range.enabled = true;
    Simulation sim(def);
    ASSERT_TRUE(sim.step()) << sim.divergence();
    const MemoryUse m = sim.memory();
    const int64_t n = sim.model().size();
    const int64_t springs = static_cast<int64_t>(sim.model().springs.size());
    // Positions, velocities, anchors, normals; inverse masses, areas; pin flags.
    EXPECT_GE(m.state, n * int64_t{4 * sizeof(Vec3) + 2 * sizeof(double) + 1});
    EXPECT_GE(m.model, springs * int64_t{sizeof(Spring)} +
                           static_cast<int64_t>(sim.model().triangles.size() * sizeof(Triangle)) +
                           n * int64_t{sizeof(Vec2) + sizeof(Vec3) + sizeof(double)});
    int64_t workspace = 0;  // the arrays the method cannot do without
    switch (v.method) {
      case Method::symplectic: workspace = n * int64_t{sizeof(Vec3)}; break;  // forces
      case Method::implicit:  // seven CG vectors, a 3×3 block per spring
        workspace = 7 * n * int64_t{sizeof(Vec3)} + springs * int64_t{sizeof(Mat3)};
        break;
      case Method::xpbd:  // base, move, velocity, acceleration (3 each), inverse mass; and for
                          // line passes two λ and six per-slot arrays of the rows' and columns'
        workspace = (v.line_passes > 0 ? 21 : 13) * n *
                    (single(v) ? int64_t{sizeof(float)} : int64_t{sizeof(double)});
        break;
      case Method::fast:  // seven iterate vectors, and at least L's diagonal for each unknown
        workspace = 7 * n * int64_t{sizeof(Vec3)} + n * int64_t{sizeof(double) + sizeof(int)};
        break;
      case Method::automatic:  // xpbd's in single precision with line passes
        workspace = 21 * n * int64_t{sizeof(float)};
        break;
    }
    EXPECT_GE(m.workspace, workspace);
    EXPECT_LE(m.total(), estimated_memory(def));
    // The estimate allows implicit a factor of its system, which this cloth, soft and coarse,
    // does not need (ImplicitFactor.AFineStiffStrip... checks one that does).
    const bool factor_allowed =
        v.method == Method::implicit || (v.method == Method::automatic && def.cloth.material);
    EXPECT_GE(3 * m.total(),
              estimated_memory(def) - (factor_allowed ? SystemFactor::estimated_bytes(n) : 0));
    per_particle[k] = static_cast<double>(m.total()) / n;
  }
  if (v.method == Method::fast) {
    EXPECT_LT(per_particle[1], 1.3 * per_particle[0]);
  } else {
    EXPECT_NEAR(per_particle[1] / per_particle[0], 1.0, 0.05);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, EachMethod, ::testing::ValuesIn(kVariants), variant_name);

TEST(SinglePrecision, HalvesTheSolverArrays) {
  SceneDef def = shipped("hang");
  def.solver.method = Method::xpbd;
  const int64_t double_bytes = Simulation(def).memory().workspace;
  def.solver.precision = Precision::f32;
  const int64_t single_bytes = Simulation(def).memory().workspace;
  // Everything but the wind's force buffer (kept in double, as forces.h writes it) halves.
  EXPECT_LT(single_bytes, 0.7 * double_bytes);
  EXPECT_GT(single_bytes, 0.5 * double_bytes);
}

// ---- Stability at the frame step with stiff springs -----------------------------------------

struct StiffCase {
  Method method;
  const char* scene;
  Precision precision = Precision::f64;
};

std::string stiff_case_name(const ::testing::TestParamInfo<StiffCase>& p) {
  return std::string(to_string(p.param.method)) +
         (p.param.precision == Precision::f32 ? "_single_" : "_") + p.param.scene;
}

class StiffAtTheFrameStep : public ::testing::TestWithParam<StiffCase> {};

TEST_P(StiffAtTheFrameStep, StaysFiniteRestsAndKeepsOutOfTheSphere) {
  // 64×64, structural stiffness 1e5 N/m (h²k/m ≈ 110 at h = 1/60 s: far past any explicit
  // bound), one step per frame for implicit and fast, the default substeps for xpbd.
  SceneDef def = shipped(GetParam().scene);
  def.cloth.cols = def.cloth.rows = 64;
  def.cloth.structural.stiffness = 1e5;
  def.solver.method = GetParam().method;
  def.solver.precision = GetParam().precision;
  Simulation sim(def);
  if (def.solver.method != Method::xpbd) {
    EXPECT_EQ(sim.substeps_per_frame(), 1);
  }
  const std::string scene = GetParam().scene;
  // hang: until at rest (kinetic energy under 1e-4 J: speeds of about 1 cm/s for the 1 kg
  // cloth), at most 4 s; wind: 1 s of gusts; sphere: 2 s (it lands at about 1.2 s).
  const double seconds = scene == "hang" ? 4.0 : scene == "wind" ? 1.0 : 2.0;
  bool rested = false;
  while (sim.time() < seconds - 1e-9) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    if (scene == "hang" && sim.time() > 0.5 && sim.diagnostics().kinetic_energy < 1e-4) {
      rested = true;
      break;
    }
  }
  const Diagnostics d = sim.diagnostics();
  EXPECT_TRUE(d.finite);
  EXPECT_EQ(d.pinned_drift, 0.0);
  if (scene == "hang") {
    EXPECT_TRUE(rested) << "kinetic energy " << d.kinetic_energy;
  }
  if (scene == "sphere") {
    EXPECT_EQ(d.max_penetration, 0.0);  // contacts are resolved last in every substep
  }
}

INSTANTIATE_TEST_SUITE_P(
    NewMethods, StiffAtTheFrameStep,
    ::testing::Values(StiffCase{Method::implicit, "hang"}, StiffCase{Method::implicit, "wind"},
                      StiffCase{Method::implicit, "sphere"}, StiffCase{Method::fast, "hang"},
                      StiffCase{Method::fast, "wind"}, StiffCase{Method::fast, "sphere"},
                      StiffCase{Method::xpbd, "hang"}, StiffCase{Method::xpbd, "wind"},
                      StiffCase{Method::xpbd, "sphere"},
                      StiffCase{Method::xpbd, "wind", Precision::f32},
                      StiffCase{Method::xpbd, "sphere", Precision::f32}),
    stiff_case_name);

TEST(SinglePrecision, RestsWhereDoubleRests) {
  // The stiff 64×64 hang with long-range attachments at its automatic 336 substeps per frame
  // (h = 5e-5 s: a step's move, g·h² = 2.4e-8 m, is under half a float ulp of |x| ≈ 1 m, so
  // positions stored whole in float would never fall; the solver keeps base + move). The
  // cloth comes to rest (under 1e-4 J, as above) within 1% strain, and every particle within
  // 1 mm (0.05% of the 2 m cloth) of where double precision puts it.
  SceneDef def = shipped("hang");
  def.cloth.cols = def.cloth.rows = 64;
  def.cloth.structural.stiffness = 1e5;
  def.cloth.long_range.enabled = true;
  def.solver.method = Method::xpbd;
  auto settle = [](const SceneDef& d) {
    Simulation sim(d);
    while (sim.time() < 4.0 - 1e-9) EXPECT_TRUE(sim.step()) << sim.divergence();
    return sim;
  };
  const Simulation reference = settle(def);
  def.solver.precision = Precision::f32;
  const Simulation single = settle(def);
  const Diagnostics d = single.diagnostics();
  EXPECT_LT(d.kinetic_energy, 1e-4);
  EXPECT_LE(d.max_strain, 0.01);
  EXPECT_EQ(d.pinned_drift, 0.0);
  double apart = 0.0;
  for (int32_t i = 0; i < single.model().size(); ++i)
    apart = std::max(apart, (single.state().x[i] - reference.state().x[i]).norm());
  EXPECT_LT(apart, 1e-3);
}

// ---- Same physics: static equilibrium and attachments --------------------------------------

TEST(StaticEquilibrium, FourCornerSagMatchesSymplecticWithEveryMethod) {
  // A horizontal 16×16 cloth pinned at its four corners sags to rest. Spring damping 2 N·s/m
  // so the symplectic reference settles within 12 s. xpbd needs 200 substeps (not its
  // automatic 12): with one Gauss–Seidel sweep per substep the cloth-wide stiffness converges
  // slowly, and at 12 substeps it sags about 25% further; at 200 it is within 1%.
  SceneDef def;
  def.cloth.cols = def.cloth.rows = 16;
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.origin = Vec3(-1.0, 1.0, -1.0);
  def.cloth.pins = {{0, 0}, {-1, 0}, {0, -1}, {-1, -1}};
  def.cloth.perturbation = 0.0;
  def.cloth.structural.damping = def.cloth.shear.damping = 2.0;
  testing_support::expect_every_method_rests_where_symplectic_does(def);
}

class LongRangeOnHang : public ::testing::TestWithParam<Variant> {};

TEST_P(LongRangeOnHang, KeepsStructuralStrainWithinOnePercent) {
  // hang at 64×64 with its default springs, which alone stretch about 3% under the cloth's
  // weight (the point pins concentrate it); with attachments at slack 0 the strain at rest
  // stays within 1% for every method. 2 s is enough to settle with attachments on.
  SceneDef def = with(shipped("hang"), GetParam());
  def.cloth.cols = def.cloth.rows = 64;
  def.cloth.long_range.enabled = true;
  Simulation sim(def);
  while (sim.time() < 2.0 - 1e-9) ASSERT_TRUE(sim.step()) << sim.divergence();
  const Diagnostics d = sim.diagnostics();
  EXPECT_LT(d.kinetic_energy, 1e-3);
  EXPECT_LE(d.max_strain, 0.01);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, LongRangeOnHang, ::testing::ValuesIn(kVariants),
                         variant_name);

TEST(LongRange, SlackAllowsThatMuchMoreDistanceFromEachPin) {
  // With slack s, no free particle ends farther from a pin than (1 + s)·its rest distance.
  SceneDef def = shipped("hang");
  def.cloth.cols = def.cloth.rows = 16;
  def.cloth.structural.stiffness = 200.0;  // soft: without the limit it would stretch ~20%
  def.cloth.long_range = {true, 0.05};
  Simulation sim(def);
  for (int f = 0; f < 60; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const ClothModel& m = sim.model();
  double worst = 0.0, tightest = 1e9;
  for (int32_t a : {m.index(0, 0), m.index(m.grid.cols - 1, 0)}) {
    for (int32_t p = 0; p < m.size(); ++p) {
      if (p == a) continue;
      const double rest = (m.rest_position[p] - m.rest_position[a]).norm();
      const double ratio = (sim.state().x[p] - sim.state().x[a]).norm() / rest;
      worst = std::max(worst, ratio);
      tightest = std::min(tightest, 1.05 - ratio);
    }
  }
  EXPECT_LE(worst, 1.05 + 1e-12);  // the projection is the last word on positions
  EXPECT_LT(tightest, 0.01);       // and the limit is reached: the soft cloth leans on it
}

// ---- Scene keys --------------------------------------------------------------------------

TEST(SolverKeys, MethodsAndLongRangeReadWriteAndRoundTrip) {
  using nlohmann::json;
  const json base = io::to_json(SceneDef{});
  for (const char* m : {"symplectic", "implicit", "xpbd", "fast"}) {
    json j = base;
    j["solver"]["method"] = m;
    EXPECT_STREQ(to_string(io::parse_scene(j, "t").solver.method), m);
  }
  json j = base;
  j["cloth"]["long_range"] = true;
  EXPECT_TRUE(io::parse_scene(j, "t").cloth.long_range.enabled);
  EXPECT_EQ(io::parse_scene(j, "t").cloth.long_range.slack, 0.0);
  j["cloth"]["long_range"] = json{{"slack", 0.1}};
  const SceneDef def = io::parse_scene(j, "t");
  EXPECT_TRUE(def.cloth.long_range.enabled);
  EXPECT_EQ(def.cloth.long_range.slack, 0.1);
  EXPECT_EQ(io::to_json(io::parse_scene(io::to_json(def), "t")), io::to_json(def));
  j["solver"]["iterations"] = 7;
  j["solver"]["stiff_sweeps"] = 3;
  j["solver"]["cg_tolerance"] = 1e-7;
  j["solver"]["cg_max_iterations"] = 99;
  j["solver"]["chebyshev_rho"] = 0.5;
  j["solver"]["method"] = "xpbd";
  j["solver"]["precision"] = "single";
  const SceneDef s = io::parse_scene(j, "t");
  EXPECT_EQ(s.solver.precision, Precision::f32);
  EXPECT_EQ(s.solver.iterations, 7);
  EXPECT_EQ(s.solver.stiff_sweeps, 3);
  EXPECT_EQ(s.solver.cg_tolerance, 1e-7);
  j["solver"]["stiff_sweeps"] = 1;  // with line passes: after them
  j["solver"]["line_passes"] = 5;
  j["solver"]["line_relaxation"] = 1.5;
  j["cloth"]["long_range"] = true;  // the default cloth is pinned
  const SceneDef l = io::parse_scene(j, "t");
  EXPECT_EQ(l.solver.line_passes, 5);
  EXPECT_EQ(l.solver.stiff_sweeps, 1);
  EXPECT_EQ(l.solver.line_relaxation, 1.5);
  EXPECT_EQ(io::to_json(io::parse_scene(io::to_json(l), "t")), io::to_json(l));
  EXPECT_EQ(s.solver.cg_max_iterations, 99);
  EXPECT_EQ(s.solver.chebyshev_rho, 0.5);
  EXPECT_EQ(io::to_json(io::parse_scene(io::to_json(s), "t")), io::to_json(s));
}

TEST(SolverKeys, BadValuesNameTheFieldAndTheProblem) {
  using nlohmann::json;
  auto error = [](const std::function<void(json&)>& edit) {
    json j = io::to_json(SceneDef{});
    edit(j);
    try {
      io::parse_scene(j, "scene.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error([](json& j) { j["cloth"]["long_range"] = "yes"; }).find("cloth.long_range"),
            std::string::npos);
  EXPECT_NE(error([](json& j) {
              j["cloth"]["long_range"] = json{{"slak", 0.1}};
            }).find("did you mean \"slack\""),
            std::string::npos);
  EXPECT_NE(error([](json& j) {
              j["cloth"]["long_range"] = json{{"slack", -1}};
            }).find("cloth.long_range.slack"),
            std::string::npos);
  EXPECT_NE(error([](json& j) { j["solver"]["cg_tolerance"] = 0; }).find("solver.cg_tolerance"),
            std::string::npos);
  EXPECT_NE(error([](json& j) { j["solver"]["chebyshev_rho"] = 1; }).find("solver.chebyshev_rho"),
            std::string::npos);
  EXPECT_NE(error([](json& j) { j["solver"]["iterations"] = -1; }).find("solver.iterations"),
            std::string::npos);
  EXPECT_NE(
      error([](json& j) { j["solver"]["stiff_sweeps"] = 10001; }).find("solver.stiff_sweeps"),
      std::string::npos);
  EXPECT_NE(error([](json& j) { j["solver"]["line_passes"] = -1; }).find("solver.line_passes"),
            std::string::npos);
  for (const double omega : {0.0, 2.0, -1.0, std::nan("")}) {
    const std::string bad = error([&](json& j) { j["solver"]["line_relaxation"] = omega; });
    EXPECT_NE(bad.find("solver.line_relaxation"), std::string::npos) << bad;
  }
  const std::string pinned = error([](json& j) {
    j["solver"]["method"] = "xpbd";
    j["solver"]["line_passes"] = 2;
  });
  EXPECT_NE(pinned.find("solver.line_passes"), std::string::npos) << pinned;
  EXPECT_NE(pinned.find("cloth.long_range"), std::string::npos) << pinned;
  EXPECT_NE(error([](json& j) { j["solver"]["method"] = "implict"; }).find("\"implicit\""),
            std::string::npos);
  EXPECT_NE(error([](json& j) { j["solver"]["precision"] = "half"; }).find("\"single\""),
            std::string::npos);
  // Single precision is xpbd's alone: asking another method for it is an error, not ignored.
  const std::string other = error([](json& j) {
    j["solver"]["method"] = "implicit";
    j["solver"]["precision"] = "single";
  });
  EXPECT_NE(other.find("solver.precision"), std::string::npos) << other;
  EXPECT_NE(other.find("xpbd"), std::string::npos) << other;
}

TEST(XpbdStiffSweeps, ConvergeTheStiffestSpringsToTheirRestLength) {
  // Stiff sweeps are Gauss–Seidel projections of the structural springs alone, each from λ = 0.
  // A grid's structural springs can all be at rest length at once (the flat cloth is one such
  // state), so repeated sweeps must drive their strain towards zero whatever the softer springs
  // and gravity did before them: fewer sweeps leave more, and enough leave none. One frame of
  // one substep of an 8×8 cloth hanging from one corner (no contacts or attachments after the
  // sweeps; with both top corners pinned the top row would be a taut string, whose sag the
  // sweeps remove only at second order). Without damping on those springs: XPBD's damping term
  // balances C against the spring's velocity, so with it the sweeps settle on a small C instead.
  SceneDef def = shipped("hang");
  def.solver.method = Method::xpbd;
  def.cloth.cols = def.cloth.rows = 8;
  def.cloth.pins = {{0, 0}};
  def.cloth.structural.damping = 0.0;
  def.solver.substeps = 1;
  double previous = 0.0;
  for (const int sweeps : {0, 1, 10, 100, 1000}) {
    def.solver.stiff_sweeps = sweeps;
    Simulation sim(def);
    ASSERT_TRUE(sim.step()) << sim.divergence();
    const double strain = sim.diagnostics().max_strain;
    SCOPED_TRACE("stiff sweeps " + std::to_string(sweeps) + ": strain " + std::to_string(strain));
    if (sweeps == 0) {
      EXPECT_GT(strain, 1e-3);  // one substep of a frame leaves the cloth stretched
    } else {
      EXPECT_LT(strain, previous);
    }
    previous = strain;
  }
  EXPECT_LT(previous, 1e-9);
}

TEST(XpbdStiffSweeps, KeepClothFoldingOffASphereFromCompressing) {
  // The benchmark's cloth (structural 1e5 N/m) dropped on its sphere, 48×48. Under its own weight
  // its structural springs change length by parts in 1e5, so any compression beyond the bench's
  // 1% bar is the solver's. Stiff sweeps resolve the contacts as they go: with contacts only at
  // each substep's end they converged against them where the cloth folds off the sphere and
  // left 1.25% compression over the last second here (0.40% now).
  SceneDef def = bench_scene("drape");
  def.solver.method = Method::xpbd;
  def.cloth.cols = def.cloth.rows = 48;
  def.solver.substeps = 16;
  def.solver.stiff_sweeps = 18;
  Simulation sim(def);
  const int frames = static_cast<int>(std::lround(3.0 / def.solver.dt));
  double compression = 0.0;
  for (int frame = 1; frame <= frames; ++frame) {
    ASSERT_TRUE(sim.step()) << sim.divergence();
    if (frame < frames - 60) continue;  // the last second: the cloth has landed and settled
    for (const Spring& s : sim.model().springs) {
      if (s.kind != SpringKind::structural) continue;
      const double length = (sim.state().x[s.j] - sim.state().x[s.i]).norm();
      compression = std::max(compression, 1.0 - length / s.rest);
    }
  }
  EXPECT_LT(compression, 0.01);
  EXPECT_LT(sim.diagnostics().max_penetration, 0.005);  // 1% of the radius, as the bench asks
}

// ---- xpbd's line passes ----------------------------------------------------------------------

/// One substep of xpbd on `def`'s cloth from `x` (at rest), with no gravity; returns the largest
/// structural strain after it.
double strain_after_one_substep(SceneDef def, const std::function<void(std::vector<Vec3>&)>& move) {
  def.forces.gravity = Vec3::Zero();
  def.solver.substeps = 1;
  const ClothModel model = build_model(def.cloth);
  ClothState state = initial_state(def.cloth, model);
  move(state.x);
  const std::vector<Collider> colliders;
  LongRange attachments;
  attachments.prepare(model, state, def.cloth.long_range);
  World world{model, state, def.forces, colliders, 0.0, attachments};
  const std::unique_ptr<Solver> solver = make_solver(def.solver, model);
  solver->prepare(world, def.solver);
  solver->step_frame(world, def.solver.dt);
  double strain = 0.0;
  for (const Spring& s : model.springs)
    if (s.kind == SpringKind::structural)
      strain = std::max(strain, std::abs((state.x[s.j] - state.x[s.i]).norm() / s.rest - 1.0));
  return strain;
}

// A micrometre cloth 2 m from the origin: its grid's rest lengths differ by the rounding of
// the positions they are measured between (in the eighth digit), which the grid path once took
// for a malformed model and aborted on. It falls as one, unstretched.
TEST(XpbdGrid, TakesAMicrometreClothFarFromTheOrigin) {
  SceneDef def = testing_support::bare(Method::xpbd);
  def.cloth.width = def.cloth.height = 1e-6;
  def.cloth.origin = Vec3(-1.0, 2.1, 0.0);
  def.forces.gravity = Vec3(0.0, -9.81, 0.0);
  Simulation sim(def);
  const double top = sim.state().x[0].y();
  for (int f = 0; f < 6; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  EXPECT_LT(sim.state().x[0].y(), top - 0.01);  // fell: ½·g·(0.1 s)² is 4.9 cm
  EXPECT_LT(sim.diagnostics().max_strain, 1e-6);
}

TEST(XpbdLinePasses, RemoveAUniformStretchInOnePassAtAnyResolution) {
  // A flat cloth stretched 1% in both directions: every structural spring is 1% long and keeps
  // its direction. A row's exact solve is then exact outright (the constraints are linear along
  // a straight chain), and the columns' solve moves whole rows without turning them, so one pass
  // leaves every structural spring at its rest length to round-off, however many particles a
  // row holds. Sweeping spring by spring moves the stretch one spring per sweep: at 64×64 a
  // sweep of all springs leaves almost all of it. Only structural springs, so nothing else
  // pulls, and rigid ones, so that the step's compliance leaves no stretch of its own. 37 × 13
  // leaves the row solve's groups of rows (8 or 16, the lanes of a vector) and tiles of columns
  // a residue partly filled, and 150 × 21 full tiles and groups before partial ones; the column
  // solve meets from both ends at a twist, which 8 × 8 puts below the first row and 5 × 2 on the
  // only constraint of each column. In single precision too, whose row solve has lanes of its
  // own width, to float's round-off (1.3e-5 along the rows of 150), far below the 1% left where
  // a lane or a column of a tile were missed.
  for (const Precision precision : {Precision::f64, Precision::f32}) {
    for (const auto& [n, rows] : {std::pair{8, 8}, {64, 64}, {37, 13}, {150, 21}, {5, 2}}) {
      SCOPED_TRACE("resolution " + std::to_string(n) + "x" + std::to_string(rows) +
                   (precision == Precision::f32 ? ", single" : ", double"));
      SceneDef def = bare(Method::xpbd);
      def.solver.precision = precision;
      def.cloth.cols = n;
      def.cloth.rows = rows;
      def.cloth.shear.stiffness = def.cloth.bending.stiffness = 0.0;
      def.cloth.structural = {1e14, 0.0};  // rigid: compliance leaves no stretch of its own
      auto stretch = [](std::vector<Vec3>& x) {
        for (Vec3& p : x) p.head<2>() *= 1.01;  // a vertical cloth: its plane is x–y
      };
      def.solver.line_passes = 1;
      EXPECT_LT(strain_after_one_substep(def, stretch),
                precision == Precision::f32 ? 1e-4 : 1e-12);
      def.solver.line_passes = 0;
      def.solver.stiff_sweeps = 1;
      EXPECT_GT(strain_after_one_substep(def, stretch), n > 8 ? 0.009 : 1e-4);
    }
  }
}

TEST(XpbdLinePasses, ConvergeACrumpledClothsStructuralSpringsInAFewPasses) {
  // A cloth crumpled out of its plane (0.2 m deep at 16×16): its rows and columns bend and cross
  // at angles, so a pass is one Newton step for each chain and block Gauss–Seidel between rows
  // and columns. Each pass must leave far less strain than the last, and eight none to
  // round-off (1.7%, 0.05%, 5e-7 and 3e-12 after 1, 2, 4 and 8 passes when written). Plain
  // passes: over-relaxed ones overshoot what a pass solves exactly.
  SceneDef def = bare(Method::xpbd);
  def.solver.line_relaxation = 1.0;
  def.cloth.cols = def.cloth.rows = 16;
  def.cloth.shear.stiffness = def.cloth.bending.stiffness = 0.0;
  def.cloth.structural = {1e14, 0.0};
  auto crumple = [](std::vector<Vec3>& x) {
    for (Vec3& p : x) p.z() += 0.2 * std::sin(3.0 * p.x()) * std::cos(2.0 * p.y());
  };
  double previous = 1.0;
  for (const int passes : {1, 2, 4, 8}) {
    def.solver.line_passes = passes;
    const double strain = strain_after_one_substep(def, crumple);
    SCOPED_TRACE(std::to_string(passes) + " passes: strain " + std::to_string(strain));
    EXPECT_LT(strain, passes == 1 ? 0.05 : 0.1 * previous);
    previous = strain;
  }
  EXPECT_LT(previous, 1e-10);
}

TEST(XpbdLinePasses, OverRelaxedPassesEndOnTheSameStepAsOneExactPass) {
  // A compliant cloth stretched 1% in both directions: one pass solves its substep's linear
  // system exactly (see above), leaving the stretch its compliance keeps. Passes over-relaxed
  // by ω (all but the last) overshoot, or under-relaxed fall short, by 1 − ω of what is left,
  // and the last pass, plain, then lands on the same solution, provided λ took the same ω·Δλ as
  // the moves: had it not, the compliance's term α̃λ would be off and so would the result.
  SceneDef def = bare(Method::xpbd);
  def.cloth.cols = def.cloth.rows = 5;
  def.cloth.shear.stiffness = def.cloth.bending.stiffness = 0.0;
  def.cloth.structural = {100.0, 1.0};  // α̃ = 1/(k·h²) = 36, about the inverse masses (25)
  auto stretch = [](std::vector<Vec3>& x) {
    for (Vec3& p : x) p.head<2>() *= 1.01;
  };
  def.solver.line_passes = 1;
  const double exact = strain_after_one_substep(def, stretch);
  EXPECT_GT(exact, 1e-3);  // the compliance keeps a good part of the stretch
  EXPECT_LT(exact, 9e-3);  // and the pass removes a good part
  for (const auto& [passes, omega] : {std::pair{3, 1.5}, {2, 1.9}, {4, 0.6}}) {
    SCOPED_TRACE(std::to_string(passes) + " passes at ω = " + std::to_string(omega));
    def.solver.line_passes = passes;
    def.solver.line_relaxation = omega;
    EXPECT_NEAR(strain_after_one_substep(def, stretch), exact, 1e-12);
  }
}

TEST(XpbdLinePasses, MeetTheBenchBarOnADrapeWhereAsManyStiffSweepsDoNot) {
  // The benchmark's cloth (structural 1e5 N/m) dropped on its sphere, 48×48, 4 substeps a frame.
  // Its own weight changes its springs' lengths by parts in 1e5, so strain beyond the bench's 1%
  // bar is the solver's. With 4 line passes a substep it stays under the bar over the last
  // second (0.53%); 4 stiff sweeps, the same structural springs swept spring by spring, leave
  // 7%. And nothing ends inside the sphere. Over-relaxed passes (the default ω = 1.3) converge
  // what block Gauss–Seidel leaves between rows and columns faster: the largest strain, averaged
  // over the last second's frames, 0.27% against 0.48% for plain passes (0.046% against 0.135%
  // at 6 passes) when written. One stiff sweep after the passes takes out most of the local
  // strain they leave at folds and where friction holds the cloth on the sphere: 0.19% at worst
  // against 0.30% (0.22% against 0.53% with the perturbation of 1e-4 m it had when written: the
  // folds, and so the figures, depend on it; over perturbations of 1 to 3 per mille of an edge
  // the sweep left 35 to 65% of the worst strain); a sweep before them, which the passes undo,
  // left 0.42%.
  struct Strain {
    double worst = 0.0, mean = 0.0;  // of each frame's largest, over the last second
  };
  auto last_second = [](int line_passes, int stiff_sweeps, double relaxation = 1.3) {
    SceneDef def = bench_scene("drape");
    def.solver.method = Method::xpbd;
    def.cloth.cols = def.cloth.rows = 48;
    def.solver.substeps = 4;
    def.solver.line_passes = line_passes;
    def.solver.stiff_sweeps = stiff_sweeps;
    def.solver.line_relaxation = relaxation;
    Simulation sim(def);
    Strain strain;
    for (int frame = 1; frame <= 300; ++frame) {
      EXPECT_TRUE(sim.step()) << sim.divergence();
      if (frame <= 240) continue;
      strain.worst = std::max(strain.worst, sim.diagnostics().max_strain);
      strain.mean += sim.diagnostics().max_strain / 60;
    }
    EXPECT_LT(sim.diagnostics().max_penetration, 0.005);  // 1% of the radius, as the bench asks
    std::printf("%d passes (ω %.1f), %d sweeps: largest strain %.3f%%, mean %.3f%%\n", line_passes,
                relaxation, stiff_sweeps, 100 * strain.worst, 100 * strain.mean);
    return strain;
  };
  const Strain relaxed = last_second(4, 0);
  EXPECT_LT(relaxed.worst, 0.01);
  EXPECT_GT(last_second(0, 4).worst, 0.02);
  EXPECT_LT(relaxed.mean, 0.75 * last_second(4, 0, 1.0).mean);
  EXPECT_LT(last_second(4, 1).worst, 0.75 * relaxed.worst);
}

TEST(XpbdLinePasses, PauseWhileTheHandHoldsAParticle) {
  // Exact chains are rigid, and rigid chains carrying a cloth's weight to one held particle
  // oscillate at large steps; so while a particle is held (and no attachment holds it), xpbd
  // sweeps its structural springs one by one, exactly as without line passes, and goes back to
  // them once it is let go.
  SceneDef def = bench_scene("drape");
  def.solver.method = Method::xpbd;
  def.cloth.cols = def.cloth.rows = 16;
  def.solver.substeps = 4;
  Simulation plain(def);
  def.solver.line_passes = 4;
  Simulation lines(def);
  for (Simulation* sim : {&plain, &lines}) {
    sim->grab(0);
    sim->move_grab(sim->state().x[0] + Vec3(0.0, 0.2, 0.0));
    for (int f = 0; f < 20; ++f) ASSERT_TRUE(sim->step()) << sim->divergence();
  }
  for (int32_t i = 0; i < plain.model().size(); ++i)
    ASSERT_EQ(lines.state().x[i], plain.state().x[i]) << "particle " << i;
  for (Simulation* sim : {&plain, &lines}) {
    sim->release();
    for (int f = 0; f < 20; ++f) ASSERT_TRUE(sim->step()) << sim->divergence();
  }
  EXPECT_LT(lines.diagnostics().max_strain, 0.5 * plain.diagnostics().max_strain);
}

TEST(XpbdSubsteps, AutomaticSubstepsReachTheSpringsStiffness) {
  // m/h² ≥ k for the stiffest spring at its lighter end: h ≤ sqrt(m/k).
  SceneDef def = shipped("hang");
  def.solver.method = Method::xpbd;
  Simulation sim(def);
  const double m = def.cloth.mass / (def.cloth.cols * def.cloth.rows);
  const double h = def.solver.dt / sim.substeps_per_frame();
  EXPECT_GE(m / (h * h), def.cloth.structural.stiffness);
  const double h_fewer = def.solver.dt / (sim.substeps_per_frame() - 1);
  EXPECT_LT(m / (h_fewer * h_fewer), def.cloth.structural.stiffness);  // and no more than that
}

}  // namespace
}  // namespace drape
