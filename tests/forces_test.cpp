// Forces against finite differences: every conservative force is the negative gradient of its
// energy, every stiffness matrix the derivative of its force; damping, drag and wind have no
// energy, so their Jacobians (or their defining formulas) are checked instead.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "drape/collider.h"
#include "drape/simulation.h"
#include "forces.h"
#include "solvers/solver.h"

namespace drape {
namespace {

constexpr double kEps = 1e-6;  // central-difference step, m (error O(eps²))

Vec3 random_vec(int seed) {
  // Fixed, well-spread test vectors; no RNG state needed.
  return Vec3(std::sin(1.3 * seed + 0.1), std::cos(2.1 * seed + 0.7), std::sin(0.7 * seed + 2.0));
}

TEST(SpringForce, IsNegativeGradientOfEnergy) {
  for (int seed = 1; seed <= 20; ++seed) {
    const Vec3 xi = random_vec(seed), xj = random_vec(seed + 100);
    const double k = 10.0 + seed, rest = 0.3 + 0.1 * seed;
    const Vec3 f = forces::spring_elastic(xi, xj, k, rest);
    for (int a = 0; a < 3; ++a) {
      Vec3 plus = xi, minus = xi;
      plus[a] += kEps;
      minus[a] -= kEps;
      const double grad = (forces::spring_energy(plus, xj, k, rest) -
                           forces::spring_energy(minus, xj, k, rest)) /
                          (2 * kEps);
      EXPECT_NEAR(f[a], -grad, 1e-6 * (1.0 + std::abs(f[a]))) << "seed " << seed << " axis " << a;
    }
  }
}

TEST(SpringForce, ObeysNewtonsThirdLaw) {
  const Vec3 xi(0.1, 0.2, 0.3), xj(1.0, -0.5, 0.7), vi(0.3, 0.0, -1.0), vj(-2.0, 1.0, 0.5);
  const Vec3 on_i =
      forces::spring_elastic(xi, xj, 50, 0.4) + forces::spring_damping(xi, xj, vi, vj, 2.0);
  const Vec3 on_j =
      forces::spring_elastic(xj, xi, 50, 0.4) + forces::spring_damping(xj, xi, vj, vi, 2.0);
  EXPECT_LT((on_i + on_j).norm(), 1e-12);
}

TEST(SpringForce, StiffnessMatrixMatchesForceDerivative) {
  for (int seed = 1; seed <= 20; ++seed) {
    const Vec3 xi = random_vec(seed), xj = random_vec(seed + 50);
    const double k = 100.0, len = (xj - xi).norm();
    // Both a stretched and a compressed spring: unclamped, the matrix is the exact derivative.
    for (double rest : {0.5 * len, 1.5 * len}) {
      const Mat3 K = forces::spring_stiffness(xi, xj, k, rest, /*clamp=*/false);
      for (int a = 0; a < 3; ++a) {
        Vec3 plus = xj, minus = xj;
        plus[a] += kEps;
        minus[a] -= kEps;
        const Vec3 column = (forces::spring_elastic(xi, plus, k, rest) -
                             forces::spring_elastic(xi, minus, k, rest)) /
                            (2 * kEps);
        EXPECT_LT((K.col(a) - column).norm(), 1e-5 * k) << "seed " << seed << " rest " << rest;
      }
    }
  }
}

TEST(SpringForce, ClampedStiffnessIsPositiveSemiDefiniteAndExactWhenStretched) {
  const Vec3 xi(0, 0, 0), xj(0.3, 0.4, 0.0);  // length 0.5
  const Mat3 compressed = forces::spring_stiffness(xi, xj, 10.0, 1.0, true);
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(compressed).eigenvalues().minCoeff(), -1e-12);
  const Mat3 stretched_clamped = forces::spring_stiffness(xi, xj, 10.0, 0.25, true);
  const Mat3 stretched_exact = forces::spring_stiffness(xi, xj, 10.0, 0.25, false);
  EXPECT_LT((stretched_clamped - stretched_exact).norm(), 1e-12);
}

TEST(SpringDamping, JacobianMatchesFiniteDifferences) {
  // f_i = c (d̂·(v_j − v_i)) d̂: linear in v, so ∂f_i/∂v_j = c d̂d̂ᵀ exactly.
  const Vec3 xi(0.1, 0.0, 0.2), xj(0.4, 0.5, -0.3), vi(1, 2, 3), vj(-1, 0.5, 0.2);
  const double c = 3.0;
  const Vec3 u = (xj - xi).normalized();
  const Mat3 expected = c * u * u.transpose();
  for (int a = 0; a < 3; ++a) {
    Vec3 plus = vj, minus = vj;
    plus[a] += kEps;
    minus[a] -= kEps;
    const Vec3 column = (forces::spring_damping(xi, xj, vi, plus, c) -
                         forces::spring_damping(xi, xj, vi, minus, c)) /
                        (2 * kEps);
    EXPECT_LT((column - expected.col(a)).norm(), 1e-8);
  }
  // It only resists motion along the spring: a transverse relative velocity gives no force.
  const Vec3 transverse = u.unitOrthogonal();
  EXPECT_LT(forces::spring_damping(xi, xj, Vec3::Zero(), transverse, c).norm(), 1e-12);
}

TEST(SpringForce, ZeroLengthSpringGivesNoNaN) {
  const Vec3 x(1, 2, 3);
  EXPECT_TRUE(forces::spring_elastic(x, x, 10, 0.5).allFinite());
  EXPECT_TRUE(forces::spring_damping(x, x, Vec3::Zero(), Vec3::Ones(), 1).allFinite());
  EXPECT_TRUE(forces::spring_stiffness(x, x, 10, 0.5, true).allFinite());
}

TEST(AirDrag, SemiImplicitUpdateMatchesQuadraticDragToFirstOrder) {
  // dv/dt = −(ρA/m)|v|v. The update v/(1 + h·(ρA/m)|v|) agrees with v − h(ρA/m)|v|v to O(h²)
  // and never reverses the velocity, whatever h.
  const double rho_a = 0.02, inv_m = 100.0;
  const Vec3 v0(3.0, -4.0, 0.0);  // |v| = 5
  for (double h : {1e-3, 1e-4, 1e-5}) {
    std::vector<Vec3> v{v0};
    forces::apply_drag(rho_a, {inv_m}, h, v);
    const Vec3 euler = v0 - h * rho_a * inv_m * v0.norm() * v0;
    EXPECT_LT((v[0] - euler).norm(), 2.0 * std::pow(h * rho_a * inv_m * 5.0, 2) * 5.0);
  }
  std::vector<Vec3> v{v0};
  forces::apply_drag(rho_a, {inv_m}, 1e3, v);  // absurd step: slows, never flips
  EXPECT_GT(v[0].dot(v0), 0.0);
  EXPECT_LT(v[0].norm(), v0.norm());
}

// A flat 2x2-particle square in the x–y plane (normal +z), 1 m², for the wind tests.
struct Square {
  Square() {
    SceneDef def;
    def.cloth.cols = def.cloth.rows = 2;
    def.cloth.width = def.cloth.height = 1.0;
    def.cloth.pins.clear();
    def.cloth.perturbation = 0.0;
    model = build_model(def.cloth);
    state = initial_state(def.cloth, model);
  }
  ClothModel model;
  ClothState state;
};

TEST(Wind, SeedModelIsTheSeedsFormula) {
  Square sq;
  WindDef w;
  w.model = WindModel::seed;
  w.strength = 2.0;
  w.coefficient = 1.5;
  for (double angle : {0.0, 0.5, 1.2}) {
    w.direction = Vec3(std::sin(angle), 0.0, std::cos(angle));  // θ = angle from the normal
    std::vector<Vec3> f(sq.model.size(), Vec3::Zero());
    forces::add_wind(sq.model, sq.state, w, 0.0, f);
    for (int32_t p = 0; p < sq.model.size(); ++p) {
      // dv/dt = c·d·|cos θ|·dA/dm, so f = c·d·|cos θ|·dA with dA a third of its triangles.
      const Vec3 expected = 1.5 * 2.0 * w.direction * std::cos(angle) * sq.state.area[p];
      EXPECT_LT((f[p] - expected).norm(), 1e-12) << "angle " << angle;
    }
  }
  double total_area = 0;
  for (double a : sq.state.area) total_area += a;
  EXPECT_NEAR(total_area, 1.0, 1e-12);
}

TEST(Wind, AeroModelIsQuadraticDragOnTheNormalComponent) {
  Square sq;
  WindDef w;
  w.model = WindModel::aero;
  w.strength = 3.0;  // m/s
  w.coefficient = 1.2;
  w.density = 1.2;
  w.direction = Vec3(0.0, 0.0, 1.0);
  std::vector<Vec3> f(sq.model.size(), Vec3::Zero());
  forces::add_wind(sq.model, sq.state, w, 0.0, f);
  Vec3 total = Vec3::Zero();
  for (const Vec3& fp : f) total += fp;
  // ½ρ·C·A·u² along the normal, for a 1 m² plate facing a 3 m/s wind.
  EXPECT_NEAR(total.z(), 0.5 * 1.2 * 1.2 * 1.0 * 9.0, 1e-12);
  EXPECT_NEAR(total.x(), 0.0, 1e-12);
  EXPECT_NEAR(total.y(), 0.0, 1e-12);
  // Its Jacobian with respect to the cloth's velocity: ∂F/∂v_z = −ρ·C·A·|u·n| summed.
  const double h = 1e-6;
  for (Vec3& v : sq.state.v) v.z() = h;
  std::vector<Vec3> f_plus(sq.model.size(), Vec3::Zero());
  forces::add_wind(sq.model, sq.state, w, 0.0, f_plus);
  for (Vec3& v : sq.state.v) v.z() = -h;
  std::vector<Vec3> f_minus(sq.model.size(), Vec3::Zero());
  forces::add_wind(sq.model, sq.state, w, 0.0, f_minus);
  double d_total = 0;
  for (int32_t p = 0; p < sq.model.size(); ++p) d_total += (f_plus[p].z() - f_minus[p].z()) / (2 * h);
  EXPECT_NEAR(d_total, -1.2 * 1.2 * 1.0 * 3.0, 1e-6);
}

TEST(Wind, EdgeOnWindPushesNothing) {
  Square sq;
  for (WindModel model : {WindModel::seed, WindModel::aero}) {
    WindDef w;
    w.model = model;
    w.strength = 5.0;
    w.direction = Vec3(1.0, 0.3, 0.0);  // in the cloth's plane
    std::vector<Vec3> f(sq.model.size(), Vec3::Zero());
    forces::add_wind(sq.model, sq.state, w, 0.0, f);
    for (const Vec3& fp : f) EXPECT_LT(fp.norm(), 1e-12) << to_string(model);
  }
}

TEST(Wind, GustsStayWithinTheirAmplitude) {
  WindDef w;
  w.strength = 4.0;
  w.gust = 0.5;
  w.gust_frequency = 0.7;
  double lo = 1e9, hi = -1e9;
  for (int k = 0; k < 10000; ++k) {
    const double s = forces::wind_strength(w, 0.01 * k);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  EXPECT_GE(lo, 4.0 * 0.5 - 1e-12);
  EXPECT_LE(hi, 4.0 * 1.5 + 1e-12);
  EXPECT_GT(hi - lo, 2.0);  // it does vary
}

TEST(Energy, TheWatchTakesBothEnergiesAndSeesAnyNonFiniteOrOverflowingNumber) {
  // 128×128 particles, enough to be summed in parallel; moving, out of plane.
  SceneDef def;
  def.cloth.cols = def.cloth.rows = 128;
  const ClothModel m = build_model(def.cloth);
  ClothState s = initial_state(def.cloth, m);
  for (int32_t i = 0; i < m.size(); ++i) {
    s.x[i] += 0.1 * random_vec(i);
    s.v[i] = random_vec(i + 7);
  }
  const Vec3 g(0.3, -9.81, 0.1);
  const forces::StateWatch w = forces::watch_state(m, s, g);
  EXPECT_TRUE(w.finite);
  const double kinetic = forces::kinetic_energy(m, s.v),
               gravity = forces::gravity_energy(m, s.x, g);
  EXPECT_NEAR(w.kinetic, kinetic, 1e-12 * kinetic);
  EXPECT_NEAR(w.gravity, gravity, 1e-12 * std::abs(gravity));
  // One number anywhere, in any component, NaN, infinite, or so large that its square (and so a
  // strain or an energy) overflows: whatever it does to the sums.
  for (const int32_t i : {0, 5000, m.size() - 1}) {
    for (int d = 0; d < 3; ++d) {
      for (const double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL, 1e200, -1e160}) {
        for (std::vector<Vec3>* field : {&s.x, &s.v}) {
          const double kept = (*field)[i][d];
          (*field)[i][d] = bad;
          EXPECT_FALSE(forces::watch_state(m, s, g).finite) << "particle " << i << " axis " << d;
          (*field)[i][d] = kept;
        }
      }
    }
  }
  EXPECT_TRUE(forces::watch_state(m, s, g).finite);
}

TEST(Normals, AreUnitAndAreaWeighted) {
  Square sq;
  for (const Vec3& n : sq.state.normal) EXPECT_LT((n - Vec3::UnitZ()).norm(), 1e-12);
  SceneDef def;
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.perturbation = 0;
  const ClothModel m = build_model(def.cloth);
  const ClothState s = initial_state(def.cloth, m);
  for (const Vec3& n : s.normal) EXPECT_LT((n - Vec3::UnitY()).norm(), 1e-12);
}

TEST(Normals, OnACrumpledGridAreEachTrianglesCrossProductSummedAtItsCorners) {
  // 7 × 5, so that rows and columns cannot be mixed up, crumpled out of its plane.
  SceneDef def;
  def.cloth.cols = 7;
  def.cloth.rows = 5;
  ClothModel m = build_model(def.cloth);
  ClothState s = initial_state(def.cloth, m);
  for (int32_t p = 0; p < m.size(); ++p) s.x[p] += 0.3 * random_vec(p);
  update_normals(m, s);
  // The definition, scattered triangle by triangle.
  std::vector<Vec3> sum(m.size(), Vec3::Zero());
  std::vector<double> twice_area(m.size(), 0.0);
  for (const Triangle& t : m.triangles) {
    const Vec3 cross = (s.x[t[1]] - s.x[t[0]]).cross(s.x[t[2]] - s.x[t[0]]);
    for (int32_t p : t) {
      sum[p] += cross;
      twice_area[p] += cross.norm();
    }
  }
  for (int32_t p = 0; p < m.size(); ++p) {
    EXPECT_LT((s.normal[p] - sum[p].normalized()).norm(), 1e-14) << p;
    EXPECT_NEAR(s.area[p], twice_area[p] / 6.0, 1e-14 * s.area[p]) << p;
  }
  // The grid's shortcut against the gather over any triangles.
  ASSERT_TRUE(m.grid_triangles);
  ClothState general = s;
  m.grid_triangles = false;
  update_normals(m, general);
  for (int32_t p = 0; p < m.size(); ++p) {
    // The same sums in another order: equal to a few units in the last place.
    EXPECT_LT((s.normal[p] - general.normal[p]).norm(), 1e-14) << p;
    EXPECT_NEAR(s.area[p], general.area[p], 1e-14 * general.area[p]) << p;
  }
}

TEST(Collider, ContactProjectsOutAndAppliesCoulombFriction) {
  ColliderDef def;
  def.type = ColliderType::plane;
  def.center = Vec3::Zero();
  def.normal = Vec3(0, 2, 0);  // normalised on use
  def.friction = 0.5;
  def.thickness = 0.01;
  const Collider c = make_collider(def);
  Vec3 x(0.0, -0.1, 0.0);
  // Normal speed 1, tangential 3: friction removes 0.5 × 1 of the tangential 3.
  Vec3 v(3.0, -1.0, 0.0);
  EXPECT_TRUE(resolve_contact(c, x, v));
  EXPECT_NEAR(x.y(), 0.01, 1e-15);
  EXPECT_NEAR(v.y(), 0.0, 1e-15);
  EXPECT_NEAR(v.x(), 2.5, 1e-12);
  // Slow tangential motion is stopped, not reversed.
  Vec3 x2(0.0, 0.0, 0.0), v2(0.1, -1.0, 0.0);
  resolve_contact(c, x2, v2);
  EXPECT_NEAR(v2.norm(), 0.0, 1e-15);
  // Separating motion is left alone.
  Vec3 x3(0.0, 0.005, 0.0), v3(1.0, 2.0, 0.0);
  resolve_contact(c, x3, v3);
  EXPECT_EQ(v3, Vec3(1.0, 2.0, 0.0));
}

TEST(Collider, PositionContactProjectsOutAndAppliesCoulombFrictionToTheMove) {
  ColliderDef def;
  def.center = Vec3(1, 2, 3);
  def.radius = 0.5;
  def.friction = 0.5;
  def.thickness = 0.01;
  const Collider c = make_collider(def);
  const PositionContact<double> contact(c);
  const Vec3 x_prev = c.center + Vec3(0, 0.51, 0);  // on the surface, at the thickness
  // Applies the contact to move m from x_prev; returns what m becomes if pushed out along the
  // normal and nothing else, and sets the normal n and the tangential part t of that move.
  Vec3 n, t;
  auto apply = [&](Vec3& m) {
    const Vec3 p = x_prev + m - c.center;
    n = p.normalized();
    const Vec3 pushed = m + (0.51 - p.norm()) * n;
    t = pushed - pushed.dot(n) * n;
    contact.apply(true, p.x(), p.y(), p.z(), m.x(), m.y(), m.z());
    return pushed;
  };
  // 0.02 in and 0.004 sideways: the slide (within 0.5 × the depth, about 0.02) is cancelled,
  // what is left of the move is along the normal.
  Vec3 m(0.004, -0.02, 0.0);
  Vec3 pushed = apply(m);
  EXPECT_GT(t.norm(), 0.003);
  EXPECT_NEAR((m - pushed.dot(n) * n).norm(), 0.0, 1e-15);
  // A slide of 0.05 is kinetic: shortened by 0.5 × the depth, in its own direction.
  m = Vec3(0.05, -0.02, 0.0);
  const double depth = 0.51 - (x_prev + m - c.center).norm();
  pushed = apply(m);
  EXPECT_NEAR((m - (pushed - 0.5 * depth * t.normalized())).norm(), 0.0, 1e-15);
  // Outside the thickness, or pinned: left as it is.
  m = Vec3(0.001, 0.02, 0.0);
  apply(m);
  EXPECT_EQ(m, Vec3(0.001, 0.02, 0.0));
  m = Vec3(0.004, -0.02, 0.0);
  const Vec3 p = x_prev + m - c.center;
  contact.apply(false, p.x(), p.y(), p.z(), m.x(), m.y(), m.z());
  EXPECT_EQ(m, Vec3(0.004, -0.02, 0.0));
  // At the very centre there is no normal: pushed straight up.
  m = Vec3::Zero();
  contact.apply(true, 0.0, 0.0, 0.0, m.x(), m.y(), m.z());
  EXPECT_NEAR((m - Vec3(0, 0.51, 0)).norm(), 0.0, 1e-15);
}

// Solvers skip runs of particles whose clearance is positive: it must be positive only where
// apply() leaves the move as it is, and it must not be needlessly cautious far from the surface.
template <typename Real>
void expect_clearance_is_safe(const Collider& c, double reach) {
  const PositionContact<Real> contact(c);
  int skipped = 0, touched = 0;
  for (int k = 0; k < 4000; ++k) {
    // Points from well inside to well outside the surface, densest near it.
    const double t = 1.5 * std::sin(0.37 * k);
    const Vec3 dir = random_vec(k).normalized();
    const Vec3 p = c.type == ColliderType::sphere
                       ? Vec3((reach + t * t * t * reach) * dir)
                       : Vec3(dir + (reach + t * t * t - dir.dot(c.normal)) * c.normal);
    const Real px = static_cast<Real>(p.x()), py = static_cast<Real>(p.y()),
               pz = static_cast<Real>(p.z());
    const Vec3 move = 0.01 * random_vec(k + 7);
    Real mx = static_cast<Real>(move.x()), my = static_cast<Real>(move.y()),
         mz = static_cast<Real>(move.z());
    const Real before[3] = {mx, my, mz};
    contact.apply(true, px, py, pz, mx, my, mz);
    const bool moved = mx != before[0] || my != before[1] || mz != before[2];
    touched += moved;
    if (contact.clearance(px, py, pz) > 0) {
      ++skipped;
      EXPECT_FALSE(moved) << "point " << k;
    }
    // 1% past the reach is clear.
    const Real far = static_cast<Real>(c.type == ColliderType::sphere ? 1.01 : 1.0 + 0.01 / reach);
    if (t > 0.5) {
      EXPECT_GT(contact.clearance(far * px, far * py, far * pz), 0) << "point " << k;
    }
  }
  EXPECT_GT(skipped, 1000);
  EXPECT_GT(touched, 1000);
}

TEST(Collider, PositionContactClearanceIsPositiveOnlyWhereTheContactDoesNothing) {
  ColliderDef sphere;
  sphere.center = Vec3(1, 2, 3);  // clearance takes x minus the centre
  sphere.radius = 0.5;
  sphere.thickness = 0.01;
  sphere.friction = 0.4;
  expect_clearance_is_safe<double>(make_collider(sphere), 0.51);
  expect_clearance_is_safe<float>(make_collider(sphere), 0.51);
  ColliderDef plane;
  plane.type = ColliderType::plane;
  plane.center = Vec3::Zero();
  plane.normal = Vec3(0.3, 1, 0.2);
  plane.thickness = 0.02;
  plane.friction = 0.4;
  expect_clearance_is_safe<double>(make_collider(plane), 0.02);
  expect_clearance_is_safe<float>(make_collider(plane), 0.02);
}

TEST(Collider, PositionContactOnAPlaneInSinglePrecision) {
  ColliderDef def;
  def.type = ColliderType::plane;
  def.center = Vec3(0, -1, 0);
  def.normal = Vec3(0, 2, 0);  // normalised on use
  def.friction = 0.0;
  def.thickness = 0.0;
  const Collider c = make_collider(def);
  const PositionContact<float> contact(c);
  // 0.1 below the plane, sliding 0.3 without friction: lifted onto it, the slide kept.
  float mx = 0.3f, my = -0.1f, mz = 0.0f;
  contact.apply(true, 0.3f, -0.1f, 0.0f, mx, my, mz);
  EXPECT_FLOAT_EQ(mx, 0.3f);
  EXPECT_EQ(my, 0.0f);
  EXPECT_EQ(mz, 0.0f);
}

TEST(Collider, SphereSignedDistance) {
  ColliderDef def;
  def.center = Vec3(1, 2, 3);
  def.radius = 0.5;
  const Collider c = make_collider(def);
  Vec3 n;
  EXPECT_NEAR(signed_distance(c, Vec3(1, 3, 3), n), 0.5, 1e-15);
  EXPECT_EQ(n, Vec3(0, 1, 0));
  EXPECT_NEAR(signed_distance(c, Vec3(1.2, 2, 3), n), -0.3, 1e-15);
}

TEST(StabilityBound, MatchesTheDampedOscillatorCondition) {
  // One free particle on a spring to a pinned one: ω² ≤ 2k/m and γ ≤ 2c/m bound the true
  // ω² = k/m, γ = c/m; the bound solves h²ω² + 2hγ = 4 for the Gershgorin values.
  SceneDef def;
  def.cloth.cols = 2;
  def.cloth.rows = 2;
  def.cloth.structural = {100.0, 0.0};
  def.cloth.shear = {0.0, 0.0};
  def.cloth.bending = {0.0, 0.0};
  def.cloth.mass = 4.0;  // 1 kg each
  const ClothModel m = build_model(def.cloth);
  const ClothState s = initial_state(def.cloth, m);
  // Each particle has 2 structural springs: Σ2k/m = 400, so h = 2/sqrt(400) = 0.1.
  EXPECT_NEAR(explicit_step_bound(m, s.inv_mass), 0.1, 1e-12);
  def.cloth.structural = {100.0, 5.0};  // γ = 2·2·5 = 20: h = 4/(20 + sqrt(400 + 1600))
  const ClothModel md = build_model(def.cloth);
  EXPECT_NEAR(explicit_step_bound(md, s.inv_mass), 4.0 / (20.0 + std::sqrt(2000.0)), 1e-12);
}

}  // namespace
}  // namespace drape
