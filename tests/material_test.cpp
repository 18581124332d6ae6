// Materials in physical units (issue 22): scene keys and presets, masses and sheet stiffness
// derived from the material at any resolution, drag by area, isometric bending against finite
// differences and against the elastica, compressed springs that yield.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "drape/error.h"
#include "drape/simulation.h"
#include "forces.h"
#include "forces/bending.h"
#include "forces/bending_damping.h"
#include "forces/bending_matrix.h"
#include "io/scene_io.h"
#include "lab/cusick.h"
#include "lab/elastica.h"
#include "model/model.h"

namespace drape {
namespace {

using nlohmann::json;

double rest_area(const ClothModel& m) {
  double a = 0.0;
  for (const Triangle& t : m.triangles) {
    const auto& x = m.rest_position;
    a += 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
  }
  return a;
}

double total(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

ClothDef material_grid(const std::string& preset, int cols, int rows, double width, double height) {
  ClothDef c;
  c.material = material_preset(preset);
  c.cols = cols;
  c.rows = rows;
  c.width = width;
  c.height = height;
  c.orientation = Orientation::horizontal;
  c.origin = Vec3(0.0, 1.0, 0.0);
  c.pins.clear();
  c.perturbation = 0.0;
  return c;
}

ClothDef material_mesh(const std::string& preset, int n) {
  ClothDef c;
  c.material = material_preset(preset);
  c.mesh = std::make_shared<ClothMesh>(shapes::jittered_grid(1.0, n, 0.3, 7));
  c.pins.clear();
  c.perturbation = 0.0;
  return c;
}

TEST(MaterialScene, PresetByNameOrObjectAndErrorsNameTheKeys) {
  SceneDef d = io::parse_scene(json::parse(R"({"cloth": {"material": "denim"}})"), "t");
  ASSERT_TRUE(d.cloth.material);
  EXPECT_EQ(d.cloth.material->density, 0.324);
  EXPECT_EQ(d.cloth.material->bending.x(), 64.196457e-6);
  // A material scene feels air by its area, not the seed's drag per particle: unset, the keys
  // take the defaults for a material's cloth; the seed's cloth keeps its drag.
  EXPECT_FALSE(d.forces.air_drag.has_value());
  EXPECT_EQ(d.forces.air_drag_for(true), 0.0);
  EXPECT_EQ(d.forces.air_density_for(true), 1.225);
  EXPECT_EQ(d.forces.air_drag_for(false), 0.01);
  EXPECT_EQ(d.forces.air_density_for(false), 0.0);

  d = io::parse_scene(json::parse(R"({"cloth": {"material": {"preset": "knit", "compression": 0.3,
                                             "bending": [1e-5, 2e-5]}},
                      "forces": {"air_drag": 0.02}})"),
                      "t");
  EXPECT_EQ(d.cloth.material->density, 0.187);
  EXPECT_EQ(d.cloth.material->compression, 0.3);
  EXPECT_EQ(d.cloth.material->bending, Vec2(1e-5, 2e-5));
  EXPECT_EQ(d.forces.air_drag, 0.02);
  // The round trip keeps it.
  const SceneDef back = io::parse_scene(io::to_json(d), "t");
  EXPECT_EQ(back.cloth.material->bending, d.cloth.material->bending);
  EXPECT_EQ(back.cloth.material->name, "knit");

  auto error = [](const char* text) {
    try {
      io::parse_scene(json::parse(text), "t");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  {
    const std::string e = error(R"({"cloth": {"material": "denim", "mass": 2}})");
    EXPECT_NE(e.find("cloth.material"), std::string::npos) << e;
    EXPECT_NE(e.find("cloth.mass"), std::string::npos) << e;
  }
  EXPECT_NE(error(R"({"cloth": {"material": "denim", "springs": {}}})").find("cloth.springs"),
            std::string::npos);
  EXPECT_NE(error(R"({"cloth": {"material": "silk"}})").find("unknown material"),
            std::string::npos);
  EXPECT_NE(error(R"({"cloth": {"material": {"density": 0.2}}})").find("cloth.material.stretch"),
            std::string::npos);
  EXPECT_NE(error(R"({"cloth": {"material": {"preset": "denim", "compression": 2}}})")
                .find("cloth.material.compression"),
            std::string::npos);
  EXPECT_NE(error(R"({"cloth": {"material": "denim"},
                      "solver": {"method": "xpbd", "line_passes": 2}})")
                .find("solver.line_passes"),
            std::string::npos);
}

TEST(MaterialModel, MassIsDensityTimesAreaAtEveryResolution) {
  for (int n : {8, 32, 64}) {
    const ClothModel m = build_model(material_grid("denim", n, n, 1.5, 1.0));
    EXPECT_NEAR(total(m.mass), 0.324 * 1.5, 1e-12) << n;
    // An inner particle carries its cell's area.
    EXPECT_NEAR(m.mass[m.index(n / 2, n / 2)], 0.324 * 1.5 / (n - 1) / (n - 1), 1e-15);
  }
  const ClothModel mesh = build_model(material_mesh("knit", 20));
  EXPECT_NEAR(total(mesh.mass), 0.187 * rest_area(mesh), 1e-12);
}

// The sheet's stiffness as the cloth's springs give it: the elastic energy per area W of a
// uniform stretch ε along u (cross direction held) is ½·S·ε², so S = 2W/ε².
double measured_stretch(const ClothModel& m, bool along_u, double shear_angle = 0.0) {
  const double eps = 1e-4;
  std::vector<Vec3> x = m.rest_position;
  for (Vec3& p : x) {
    if (shear_angle != 0.0) {
      p.x() += shear_angle * p.z();  // a simple shear γ in the x–z plane
    } else {
      (along_u ? p.x() : p.z()) *= 1.0 + eps;
    }
  }
  const double e = shear_angle != 0.0 ? shear_angle : eps;
  return 2.0 * forces::spring_energy(m, x) / rest_area(m) / (e * e);
}

TEST(MaterialModel, SheetStiffnessIsTheMaterialsOnGridsAtAnyResolution) {
  for (int n : {8, 33, 64}) {
    // Rectangular cells, to check the cross terms of dx ≠ dy too.
    const ClothModel m = build_model(material_grid("denim", n, n / 2 + 1, 1.0, 0.7));
    EXPECT_NEAR(measured_stretch(m, true), 205.352005, 1e-3 * 205.0) << n;
    EXPECT_NEAR(measured_stretch(m, false), 1013.88629, 1e-3 * 1013.0) << n;
    EXPECT_NEAR(measured_stretch(m, true, 1e-4), 53.387184, 1e-3 * 53.0) << n;
  }
}

TEST(MaterialModel, AGridsSheetHasNoFreeModeWhereTheShearExceedsTheStretch) {
  // The knit's shear (36.9 N/m) exceeds its warp stretch (16.6): a grid's diagonals carrying
  // that shear would carry all of both stretches, and warp stretched as weft shortens would
  // cost nothing. The grid takes the shear its threads allow and keeps both stretches exact.
  const MaterialDef knit = *material_preset("knit");
  for (int n : {8, 33}) {
    const ClothModel m = build_model(material_grid("knit", n, n / 2 + 1, 1.0, 0.7));
    const double dx = 1.0 / (n - 1), dy = 0.7 / (n / 2);
    const double G = model::grid_shear(knit, dx, dy);
    EXPECT_NEAR(measured_stretch(m, true), knit.stretch.x(), 1e-3 * knit.stretch.x()) << n;
    EXPECT_NEAR(measured_stretch(m, false), knit.stretch.y(), 1e-3 * knit.stretch.y()) << n;
    EXPECT_NEAR(measured_stretch(m, true, 1e-4), G, 1e-3 * G) << n;
    EXPECT_GT(G, 0.0);
    EXPECT_LT(G, knit.shear);
    // Each thread keeps its share of the stretch.
    for (const Spring& s : m.springs) {
      if (s.kind == SpringKind::structural) {
        EXPECT_GT(s.stiffness, 0.0);
      }
    }
    // ε_uu = ε, ε_vv = −ε: W = ½·(C_uu + C_vv − 2·G)·ε², G being the diagonals' coupling. The
    // diagonals give the weft G·dy²/dx² of its stiffness; its compressed threads the rest times
    // `compression`.
    const double eps = 1e-4, weft_diagonals = G * dy * dy / (dx * dx);
    const double c_vv = weft_diagonals + knit.compression * (knit.stretch.y() - weft_diagonals);
    std::vector<Vec3> x = m.rest_position;
    for (Vec3& p : x) p.x() *= 1.0 + eps, p.z() *= 1.0 - eps;
    const double mode = 2.0 * forces::spring_energy(m, x) / rest_area(m) / (eps * eps);
    EXPECT_NEAR(mode, knit.stretch.x() + c_vv - 2.0 * G, 1e-3 * mode) << n;
    EXPECT_GT(mode, 0.25 * knit.stretch.x()) << n;
  }
}

TEST(MaterialModel, SheetStiffnessOnAnIrregularMeshIsNearTheMaterials) {
  // Van Gelder's edge weights are exact for equilateral meshes only; on this jittered
  // triangulation (vertices moved by up to 0.3 of the spacing, random diagonals) a uniform
  // stretch with the cross direction held measures within the tolerance below.
  for (int n : {16, 32}) {
    const ClothModel m = build_model(material_mesh("polyester", n));
    const double su = measured_stretch(m, true), sv = measured_stretch(m, false);
    RecordProperty("stretch_u_" + std::to_string(n), std::to_string(su));
    EXPECT_NEAR(su / 2002.08618, 1.0, 0.3) << n;
    EXPECT_NEAR(sv / 2027.48559, 1.0, 0.3) << n;
    std::printf("jittered mesh %d²: measured stretch %.1f and %.1f N/m against 2002 and 2027\n", n,
                su, sv);
  }
}

TEST(MaterialModel, BendingElementsVanishFlatAndGiveTheCylindersEnergy) {
  // ½·B·κ²·area for a strip rolled onto a cylinder of radius R along u; the boundary columns'
  // edges, shared by one triangle, carry no element: half a cell missing at each end.
  const int n = 64;
  ClothDef def = material_grid("cotton-polyester", n, n, 1.0, 1.0);
  const ClothModel m = build_model(def);
  EXPECT_LT(forces::bending_energy(m, m.rest_position), 1e-20);
  const double R = 2.0, B = 125.409805e-6;
  std::vector<Vec3> x = m.rest_position;
  for (Vec3& p : x) {
    const double s = p.x();
    p.x() = R * std::sin(s / R);
    p.y() = 1.0 + R * (1.0 - std::cos(s / R));
  }
  const double expected = 0.5 * B / (R * R) * 1.0;
  EXPECT_NEAR(forces::bending_energy(m, x) / expected, 1.0 - 1.0 / (n - 1), 0.005);
}

TEST(BendingForce, IsNegativeGradientOfEnergyWithAConstantHessian) {
  const ClothModel m = build_model(material_mesh("denim", 6));
  ASSERT_FALSE(m.bending.empty());
  std::vector<Vec3> x = m.rest_position, v(m.size(), Vec3::Zero());
  for (int32_t i = 0; i < m.size(); ++i)
    x[i] += 0.05 * Vec3(std::sin(1.3 * i), std::cos(2.1 * i), std::sin(0.7 * i + 2.0));
  const double h = 1e-6;
  for (size_t e = 0; e < m.bending.size(); e += 7) {
    const BendingElement& b = m.bending[e];
    for (int k = 0; k < 4; ++k) {
      const Vec3 f = forces::bending_force(b, k, x, v);
      for (int a = 0; a < 3; ++a) {
        std::vector<Vec3> plus = x, minus = x;
        plus[b.v[k]][a] += h;
        minus[b.v[k]][a] -= h;
        const double grad =
            (forces::bending_energy(b, plus) - forces::bending_energy(b, minus)) / (2 * h);
        EXPECT_NEAR(f[a], -grad, 1e-7 * (1.0 + std::abs(f[a])));
        // ∂f_l/∂x_k = −k·w_l·w_k·I for every corner l, wherever the cloth is.
        for (int l = 0; l < 4; ++l) {
          const Vec3 df =
              (forces::bending_force(b, l, plus, v) - forces::bending_force(b, l, minus, v)) /
              (2 * h);
          for (int c = 0; c < 3; ++c) {
            const double expected = c == a ? -b.stiffness * b.w[l] * b.w[k] : 0.0;
            EXPECT_NEAR(df[c], expected, 1e-6 * (1.0 + std::abs(expected)));
          }
        }
      }
    }
    // Damping: −d·w_k·Σ w_l v_l, linear in the velocities.
    std::vector<Vec3> moving(m.size(), Vec3::Zero());
    moving[b.v[2]] = Vec3(0.0, 1.0, 0.0);
    const Vec3 fd = forces::bending_force(b, 3, m.rest_position, moving);
    EXPECT_NEAR(fd.y(), -b.damping * b.w[3] * b.w[2], 1e-15);
  }
}

// The elements gathered into K and D (forces::BendingMatrix, the rows implicit and symplectic
// multiply by) against the elements' own forces summed one by one, on an irregular mesh: the
// same force on every particle, the same combination a·K + b·D, symmetric, and built again when
// an element's stiffness changes.
TEST(BendingMatrix, RowsGiveTheElementsSummedForces) {
  ClothModel m = build_model(material_mesh("denim", 6));
  ASSERT_FALSE(m.bending.empty());
  const int32_t n = m.size();
  std::vector<Vec3> x = m.rest_position, v(n), p(n);
  for (int32_t i = 0; i < n; ++i) {
    x[i] += 0.05 * Vec3(std::sin(1.3 * i), std::cos(2.1 * i), std::sin(0.7 * i + 2.0));
    v[i] = Vec3(std::cos(0.9 * i), std::sin(1.7 * i), std::cos(0.4 * i + 1.0));
    p[i] = Vec3(std::sin(0.3 * i + 1.0), std::cos(1.1 * i), std::sin(2.3 * i));
  }
  forces::BendingMatrix matrix;
  matrix.prepare(m);
  const double a = 2.7e-4, b = 1.6e-2;
  matrix.combine(a, b);
  std::vector<Vec3> force(n, Vec3::Zero()), combined(n, Vec3::Zero());
  std::vector<double> diagonal(n, 0.0);
  for (const BendingElement& e : m.bending) {
    const Vec3 c = (a * e.stiffness + b * e.damping) * forces::bending_vector(e, p);
    for (int k = 0; k < 4; ++k) {
      force[e.v[k]] += forces::bending_force(e, k, x, v);
      combined[e.v[k]] += e.w[k] * c;
      diagonal[e.v[k]] += (a * e.stiffness + b * e.damping) * e.w[k] * e.w[k];
    }
  }
  double scale = 0.0;
  for (int32_t i = 0; i < n; ++i) scale = std::max(scale, force[i].norm());
  ASSERT_GT(scale, 0.0);
  for (int32_t i = 0; i < n; ++i) {
    EXPECT_LT((-matrix.force_row(i, x, v) - force[i]).norm(), 1e-12 * scale) << i;
    EXPECT_LT((matrix.combined_row(i, p) - combined[i]).norm(), 1e-12 * scale) << i;
    EXPECT_NEAR(matrix.combined_diagonal(i), diagonal[i], 1e-12 * (1.0 + diagonal[i])) << i;
    matrix.for_row(i, [&](int32_t j, double k, double d) {
      bool found = false;
      matrix.for_row(j, [&](int32_t l, double kt, double dt) {
        if (l != i) return;
        found = true;
        EXPECT_EQ(kt, k);
        EXPECT_EQ(dt, d);
      });
      EXPECT_TRUE(found) << i << " " << j;
    });
  }
  // A stiffer element: prepare() sees the change.
  const Vec3 before = matrix.force_row(m.bending[0].v[0], x, v);
  m.bending[0].stiffness *= 2.0;
  matrix.prepare(m);
  EXPECT_NE(matrix.force_row(m.bending[0].v[0], x, v), before);
}

// Backward Euler for the bending elements' damping, (M + dt·D)·v' = M·v, against a dense
// solve of the same system assembled here from the elements (D = Σ d·w·wᵀ per coordinate), with
// two particles pinned (their velocity given, moved to the right-hand side) and with none (then
// momentum is kept: each element's weights sum to zero). Kinetic energy only falls, and a
// rigid motion (every particle alike) is not damped at all.
TEST(BendingDamping, SolvesBackwardEulerForTheElementsDampingExactly) {
  ClothDef def = material_mesh("denim", 6);
  def.material->damping = 5.0;  // s, to damp much on cells this coarse (17 cm)
  const ClothModel m = build_model(def);
  const int32_t n = m.size();
  const double dt = 1.0 / 60.0;
  std::vector<Vec3> v0(n);
  for (int32_t p = 0; p < n; ++p)
    v0[p] = Vec3(std::sin(1.3 * p), std::cos(0.7 * p + 0.2), std::sin(2.1 * p + 1.0));
  auto energy = [&](const std::vector<Vec3>& v) {
    double e = 0.0;
    for (int32_t p = 0; p < n; ++p) e += 0.5 * m.mass[p] * v[p].squaredNorm();
    return e;
  };
  for (bool pinned : {true, false}) {
    std::vector<uint8_t> pins(n, 0);  // the first and the last particle, or none
    for (int32_t p : {int32_t{0}, n - 1}) pins.at(p) = pinned ? 1 : 0;
    std::vector<std::vector<double>> A(n, std::vector<double>(n, 0.0));
    for (int32_t p = 0; p < n; ++p) A[p][p] = m.mass[p];
    for (const BendingElement& b : m.bending)
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < 4; ++l) A[b.v[k]][b.v[l]] += dt * b.damping * b.w[k] * b.w[l];
    std::vector<Vec3> expected(n);
    for (int32_t p = 0; p < n; ++p) expected[p] = m.mass[p] * v0[p];
    for (int32_t p = 0; p < n; ++p)
      if (pins[p]) {  // v' = v: the row says so, the column moves to the right
        for (int32_t q = 0; q < n; ++q)
          if (q != p) expected[q] -= A[q][p] * v0[p], A[q][p] = A[p][q] = 0.0;
        A[p][p] = 1.0;
        expected[p] = v0[p];
      }
    // Gaussian elimination (A is symmetric positive definite: no pivoting needed).
    for (int32_t k = 0; k < n; ++k)
      for (int32_t q = k + 1; q < n; ++q) {
        const double f = A[q][k] / A[k][k];
        for (int32_t c = k; c < n; ++c) A[q][c] -= f * A[k][c];
        expected[q] -= f * expected[k];
      }
    for (int32_t k = n - 1; k >= 0; --k) {
      for (int32_t c = k + 1; c < n; ++c) expected[k] -= A[k][c] * expected[c];
      expected[k] /= A[k][k];
    }

    forces::BendingDamping damping;
    damping.prepare(m, pins, dt);
    ASSERT_FALSE(damping.empty());
    std::vector<double> vx(n), vy(n), vz(n);
    for (int32_t p = 0; p < n; ++p) vx[p] = v0[p].x(), vy[p] = v0[p].y(), vz[p] = v0[p].z();
    damping.apply(vx.data(), vy.data(), vz.data());
    std::vector<Vec3> v(n);
    double worst = 0.0;
    Vec3 momentum = Vec3::Zero(), momentum0 = Vec3::Zero();
    for (int32_t p = 0; p < n; ++p) {
      v[p] = Vec3(vx[p], vy[p], vz[p]);
      worst = std::max(worst, (v[p] - expected[p]).norm());
      momentum += m.mass[p] * v[p], momentum0 += m.mass[p] * v0[p];
    }
    EXPECT_LT(worst, 1e-12) << pinned;
    if (pinned) {
      EXPECT_EQ(v[0], v0[0]);  // untouched
    }
    std::printf("bending damping, %s: kinetic energy %.4g J -> %.4g J\n",
                pinned ? "two pinned" : "none pinned", energy(v0), energy(v));
    EXPECT_LT(energy(v), 0.9 * energy(v0)) << pinned;
    if (!pinned) {
      EXPECT_LT((momentum - momentum0).norm(), 1e-12 * momentum0.norm() + 1e-15);
    }

    // Every particle moving alike has no curvature rate: nothing to damp.
    for (int32_t p = 0; p < n; ++p) vx[p] = 0.3, vy[p] = -1.2, vz[p] = 0.5;
    damping.apply(vx.data(), vy.data(), vz.data());
    for (int32_t p = 0; p < n; ++p)
      ASSERT_LT((Vec3(vx[p], vy[p], vz[p]) - Vec3(0.3, -1.2, 0.5)).norm(), 1e-12) << p;
  }
}

// Cloth whose elements are not damped (every seed scene) has nothing to solve: the damping keeps
// no matrix and no copy of the pins or masses, however large the cloth, and one that was
// damped and is prepared again undamped lets its factorisation go.
TEST(BendingDamping, KeepsNothingForClothWithoutDamping) {
  ClothDef def = material_mesh("denim", 24);
  def.material->damping = 0.0;
  const ClothModel undamped = build_model(def);
  def.material->damping = 0.002;
  const ClothModel damped = build_model(def);
  const std::vector<uint8_t> pins(undamped.size(), 0);
  forces::BendingDamping damping;
  damping.prepare(undamped, pins, 1.0 / 60.0);
  EXPECT_TRUE(damping.empty());
  const int64_t idle = damping.bytes();
  EXPECT_LT(idle, 1024) << "bytes kept for " << undamped.size() << " particles";
  damping.prepare(damped, pins, 1.0 / 60.0);
  EXPECT_FALSE(damping.empty());
  EXPECT_GT(damping.bytes(), 100 * undamped.size());  // the factor, at least
  damping.prepare(undamped, pins, 1.0 / 60.0);
  EXPECT_TRUE(damping.empty());
  EXPECT_EQ(damping.bytes(), idle);
}

TEST(CompressedSpring, ActsWithTheSofterStiffnessAndStaysAGradient) {
  const Vec3 xi(0.0, 0.0, 0.0);
  const double k = 100.0, rest = 1.0, c = 0.1;
  for (double len : {0.8, 0.95, 1.05, 1.3}) {
    const Vec3 xj(len, 0.0, 0.0);
    const double ks = forces::acting_stiffness(xi, xj, k, rest, c);
    EXPECT_EQ(ks, len < rest ? c * k : k);
    const double h = 1e-6;
    auto energy = [&](double l) {
      const Vec3 p(l, 0.0, 0.0);
      return forces::spring_energy(xi, p, forces::acting_stiffness(xi, p, k, rest, c), rest);
    };
    const double grad = (energy(len + h) - energy(len - h)) / (2 * h);
    // Force on j is minus the force on i.
    EXPECT_NEAR(-forces::spring_elastic(xi, xj, ks, rest).x(), -grad, 1e-6);
  }
  EXPECT_EQ(forces::acting_stiffness(xi, Vec3(0.5, 0, 0), k, rest, 1.0), k);
}

// A SceneDef built in code with a material and nothing said of the air: its cloth feels sea-level
// air by its area and no drag per particle, as a scene file's does.
TEST(AreaDrag, TerminalSpeedIsTheSameAtEveryResolutionWithEveryMethod) {
  // A horizontal sheet falling flat: ½ρC·A·v² = density·A·g, v = sqrt(2·density·g/(ρC)).
  const double rho = 1.225, C = 1.2, density = 0.324, g = 9.81;
  const double expected = std::sqrt(2.0 * density * g / (rho * C));
  // xpbd and fast at smaller sizes: their fine cloths take seconds here (xpbd's automatic
  // substeps grow with the resolution; fast with a material, see the README).
  for (Method method : {Method::implicit, Method::xpbd, Method::fast}) {
    const std::vector<int> sizes =
        method == Method::implicit ? std::vector<int>{8, 16, 32} : std::vector<int>{4, 8, 16};
    for (int n : sizes) {
      SceneDef def;
      def.cloth = material_grid("denim", n, n, 0.5, 0.5);
      def.cloth.origin = Vec3(0.0, 100.0, 0.0);
      def.solver.method = method;
      Simulation sim(def);
      for (int f = 0; f < 180; ++f) ASSERT_TRUE(sim.step());
      double vy = 0.0;
      for (const Vec3& v : sim.state().v) vy += v.y();
      vy /= sim.model().size();
      // The semi-implicit drag's fixed point lies h·g/2 off the closed form (first order in
      // the substep h): below it where the drag follows gravity's kick (implicit, xpbd:
      // v(1 + h·k·(v + h·g)) = v + h·g), above where the kick follows the drag (fast, whose
      // velocity ends with it: v = v/(1 + h·k·v) + h·g). The resolution changes nothing.
      const double h = def.solver.dt / sim.substeps_per_frame(), k = 0.5 * rho * C / density;
      const double kick = method == Method::fast ? h * g : -h * g;
      const double discrete = 0.5 * (kick + std::sqrt(h * h * g * g + 4.0 * g / k));
      std::printf("terminal speed %s %d²: %.6f m/s (closed form %.5f, its step's %.6f)\n",
                  to_string(method), n, -vy, expected, discrete);
      EXPECT_NEAR(-vy / discrete, 1.0, 1e-4) << to_string(method) << " " << n;
    }
  }
}

// The seed's cloth with forces.air_density feels it with every method, xpbd on the grid too
// (whose kernels once skipped it: the sheet fell freely). Per particle the drag is ½ρC·A_i/m_i,
// A_i a third of its triangles' area, so the border, with less area than mass, leads and the
// sheet cups: no closed form. Both small-step methods, symplectic and xpbd, must agree (measured:
// 2.32 and 2.39 m/s after 2 s, the flat sheet's sqrt(2Mg/(ρC·A)) being 1.83; implicit's one
// step a frame damps the cupping: 1.93), and every method falls far slower than in vacuum.
TEST(AreaDrag, SlowsTheSeedsGridWithEveryMethod) {
  std::vector<double> speeds;
  for (Method method : {Method::symplectic, Method::xpbd, Method::implicit}) {
    SceneDef def;
    def.cloth.cols = def.cloth.rows = 12;
    def.cloth.orientation = Orientation::horizontal;
    def.cloth.pins.clear();
    def.cloth.perturbation = 0.0;
    def.cloth.origin = Vec3(0.0, 100.0, 0.0);
    def.forces.air_drag = 0.0;
    def.forces.air_density = 1.225;
    def.solver.method = method;
    Simulation sim(def);
    for (int f = 0; f < 120; ++f) ASSERT_TRUE(sim.step()) << to_string(method);
    double vy = 0.0;
    for (const Vec3& v : sim.state().v) vy += v.y() / sim.model().size();
    const double M = total(sim.model().mass), A = rest_area(sim.model());
    const double flat = std::sqrt(2.0 * M * 9.81 / (1.225 * def.forces.drag_coefficient * A));
    std::printf("seed grid with area drag, %s: mean speed %.4f m/s after 2 s (flat sheet %.4f)\n",
                to_string(method), -vy, flat);
    EXPECT_LT(-vy, 2.0 * flat) << to_string(method);  // in vacuum: 19.6 m/s, 10.7 flat speeds
    speeds.push_back(-vy);
  }
  EXPECT_NEAR(speeds[1] / speeds[0], 1.0, 0.05);
}

// The same denim draped over the sphere (scenes/sphere-denim.json) at 32, 64 and 128 cells a
// side, at rest (8 s; at the scene's 4 s the folds still slide): the shadow from above, the mean
// height and the lowest point of 64 and 128 agree within 2% and 1 cm. 32 cells (6 cm cells for
// folds about 10 cm wide) is printed, not held: its shadow is 4 to 6% larger (measured). The
// particles the grids share (every particle of the 32-cell grid is one of the finer grids') are
// printed too: folds fall in other places.
TEST(MaterialConvergence, DenimOverTheSphereEndsInTheSameShapeAt32_64And128Cells) {
  struct Shape {
    std::vector<Vec3> x;
    double area = 0.0, mean_y = 0.0, low_y = 0.0;
  };
  std::vector<Shape> shapes;
  for (int cells : {32, 64, 128}) {
    SceneDef def = io::load_scene(
        std::string(DRAPE_SOURCE_DIR) + "/scenes/sphere-denim.json",
        {"cloth.resolution=[" + std::to_string(cells + 1) + "," + std::to_string(cells + 1) + "]",
         "duration=8"});
    Simulation sim(def);
    const int frames = static_cast<int>(std::lround(def.duration / def.solver.dt));
    for (int f = 0; f < frames; ++f) ASSERT_TRUE(sim.step()) << cells;
    Shape s;
    s.x = sim.state().x;
    s.area = lab::covered_area(lab::cast_shadow(s.x, sim.model().triangles, 2.2, 1100));
    s.low_y = s.x[0].y();
    for (const Vec3& p : s.x) {
      s.mean_y += p.y() / s.x.size();
      s.low_y = std::min(s.low_y, p.y());
    }
    std::printf(
        "sphere-denim %d cells: shadow %.4f m², mean height %.4f m, lowest %.4f m, "
        "kinetic energy %.3g J\n",
        cells, s.area, s.mean_y, s.low_y, sim.diagnostics().kinetic_energy);
    shapes.push_back(std::move(s));
  }
  for (size_t k = 1; k < shapes.size(); ++k) {
    const Shape &a = shapes[0], &b = shapes[k];
    std::printf("32 cells against %d: shadow %+.2f%%, mean height %+.4f m, lowest %+.4f m\n",
                32 << k, 100.0 * (b.area / a.area - 1.0), b.mean_y - a.mean_y, b.low_y - a.low_y);
    // The 33² grid's particle (c, r) is the finer grid's (c·f, r·f).
    const int f = 1 << k, n = 33, m = 32 * f + 1;
    double worst = 0.0, mean = 0.0;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        const double d = (a.x[r * n + c] - b.x[(r * f) * m + c * f]).norm();
        worst = std::max(worst, d);
        mean += d / (n * n);
      }
    std::printf("32 cells against %d: shared particles %.4f m apart on average, %.4f at most\n",
                32 * f, mean, worst);
  }
  const Shape &coarse = shapes[1], &fine = shapes[2];
  EXPECT_NEAR(fine.area / coarse.area, 1.0, 0.02);
  EXPECT_NEAR(fine.mean_y, coarse.mean_y, 0.01);
  EXPECT_NEAR(fine.low_y, coarse.low_y, 0.01);
}

// Stiffness-proportional damping takes a mode of angular frequency ω down at β·ω²/2 (the
// modal damping ratio of Rayleigh damping is β·ω/2). A short stiff strip, clamped as in the
// elastica test below and released flat in a vacuum, swings about its sag; the peaks of its
// tip's distance from the sag (the elastica's, by shooting) fall at that rate, ω taken from
// the peaks' spacing (half a period). With β = 0 only the methods' own damping is left.
// (xpbd took a material's bending damping by one Gauss–Seidel sweep over the elements a
// frame: the strip's swing lost 0.2% of its energy a frame with 500 times the preset's β.
// fast damped the move across its stretch springs as well, by β times their stiffness: the
// swing died within fewer than six peaks.)
TEST(MaterialDamping, AStripsSwingDecaysAtTheRateRayleighDampingGives) {
  const double L = 0.05, dx = L / 16;
  const MaterialDef mat = *material_preset("cotton-polyester");
  const double sag = lab::elastica_tip(mat.bending.x(), mat.density * 9.81, L + 0.5 * dx).drop;
  for (Method method : {Method::xpbd, Method::implicit, Method::fast})
    for (double beta : {0.0, 0.01}) {
      SceneDef def;
      def.cloth = material_grid("cotton-polyester", 18, 4, L + dx, 3 * dx);
      def.cloth.material->damping = beta;
      for (int r = 0; r < 4; ++r)
        def.cloth.pins.push_back({0, r}), def.cloth.pins.push_back({1, r});
      def.forces.air_drag = 0.0;
      def.forces.air_density = 0.0;
      def.solver.dt = 1.0 / 240.0;  // about 46 frames a period
      def.solver.method = method;
      if (method != Method::xpbd) def.solver.substeps = 20;  // their own damping ω²h/2 small
      Simulation sim(def);
      std::vector<double> off;  // the tip's distance from the sag, each frame for 1 s
      for (int f = 0; f < 240; ++f) {
        ASSERT_TRUE(sim.step());
        double tip = 0.0;
        for (int r = 0; r < 4; ++r) tip += sim.state().x[sim.model().index(17, r)].y();
        off.push_back(std::abs(1.0 - tip / 4.0 - sag));
      }
      // Least squares of ln(peak) against time: the decay rate; the spacing: ω.
      double n = 0, st = 0, sa = 0, stt = 0, sta = 0, first = -1, last = -1;
      for (size_t k = 1; k + 1 < off.size(); ++k) {
        if (!(off[k] > off[k - 1] && off[k] >= off[k + 1])) continue;
        const double t = k * def.solver.dt, a = std::log(off[k]);
        n += 1, st += t, sa += a, stt += t * t, sta += t * a;
        if (first < 0) first = t;
        last = t;
      }
      ASSERT_GE(n, 6) << to_string(method) << " " << beta;
      const double rate = -(n * sta - st * sa) / (n * stt - st * st);
      const double omega = std::numbers::pi * (n - 1) / (last - first);
      const double expected = 0.5 * beta * omega * omega;
      std::printf("%s, β = %.3g s: ω %.1f rad/s, peaks fall at %.2f /s (β·ω²/2 = %.2f /s)\n",
                  to_string(method), beta, omega, rate, expected);
      if (beta > 0.0)
        EXPECT_NEAR(rate / expected, 1.0, 0.15) << to_string(method);
      else
        EXPECT_LT(std::abs(rate), 0.5) << to_string(method);
    }
}

// A stiff and a soft preset, each held to 5% from coarse to fine (the figures are in the
// README). The knit's stretch (16.6 N/m) is two orders below the others'; before its grid took
// the shear its threads allow (model::grid_shear) it stretched 11% along the strip and sagged 9%
// more. The strip feels the air a scene file gives a material's cloth (drag by area, none per
// particle): the seed's drag per particle, the default of a SceneDef built in code, holds a
// fine strip's light particles back so hard that at 64 cells it was 57% short after 4 s.
// `implicit` at its one substep a frame comes to rest within 2 s; `xpbd` at its automatic
// substeps swings on for longer, as the material's small damping lets it (see
// MaterialDamping above), so the drop is the mean over the last 2 of 8 s, for both. `xpbd` is left
// out at 64 cells for its cost (2164 substeps a frame).
struct StripCase {
  const char* preset;
  double length;  // m, long enough for a drop of about two thirds of it
};

// A fine strip of stiff fabric is where block-Jacobi CG is weak (hundreds of iterations a
// substep): `implicit` makes a factor of its system there (SystemFactor), and what it holds
// stays under the estimate the memory budget is checked against.
TEST(ImplicitFactor, AFineStiffStripTakesOneAndStaysUnderTheMemoryEstimate) {
  SceneDef def;
  def.cloth = material_grid("denim", 82, 4, 0.2, 0.0075);
  def.cloth.pins.clear();
  for (int r = 0; r < 4; ++r) def.cloth.pins.push_back({0, r}), def.cloth.pins.push_back({1, r});
  def.solver.method = Method::implicit;
  Simulation sim(def);
  for (int f = 0; f < 30; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  const int64_t n = sim.model().size();
  // Block-Jacobi CG's arrays take under 800 B a particle (the seed's hang: 781 to 789 B); with
  // a factor (L and the matrix it is made from) over twice that: 2.8 KB a particle here.
  EXPECT_GT(sim.memory().workspace, 2 * 1024 * n);
  EXPECT_LE(sim.memory().total(), estimated_memory(def));
  // The hand takes the tip (a new preparation, the factor kept: lagged, a sound
  // preconditioner still) and lifts it 5 cm: the tip goes where the hand says and the strip
  // rises with it.
  const int32_t tip = sim.model().index(81, 1), near = sim.model().index(70, 1);
  const Vec3 lifted = sim.state().x[tip] + Vec3(0.0, 0.05, 0.0);
  const double near_before = sim.state().x[near].y();
  sim.grab(tip);
  for (int f = 0; f < 30; ++f) {
    sim.move_grab(lifted);
    ASSERT_TRUE(sim.step()) << sim.divergence();
  }
  EXPECT_TRUE(sim.state().x[tip].isApprox(lifted, 1e-12));
  EXPECT_GT(sim.state().x[near].y(), near_before + 0.01);  // 11 cells in: 1.6 cm
}

class Elastica : public ::testing::TestWithParam<StripCase> {};

TEST_P(Elastica, AClampedStripSagsAsTheShootingSolutionFromCoarseToFine) {
  // Peirce's cantilever: a strip along the warp (u), its first two columns pinned (the clamp,
  // so θ(0) = 0 at the second), its free length L beyond them.
  const char* preset = GetParam().preset;
  const double L = GetParam().length;
  const MaterialDef mat = *material_preset(preset);
  const double w = mat.density * 9.81, B = mat.bending.x();
  for (Method method : {Method::implicit, Method::xpbd})
    for (int cells : {8, 16, 32, 64}) {
      if (method == Method::xpbd && cells == 64) continue;
      const double dx = L / cells;
      // The clamp holds the segment between the last two pinned columns level: the strip is
      // clamped at its middle, half a cell before the second column.
      const double expected = lab::elastica_tip(B, w, L + 0.5 * dx).drop;
      SceneDef def;
      def.cloth = material_grid(preset, cells + 2, 4, L + dx, 3 * dx);
      def.cloth.pins.clear();
      for (int r = 0; r < 4; ++r)
        def.cloth.pins.push_back({0, r}), def.cloth.pins.push_back({1, r});
      def.solver.method = method;  // the air: a material's (by area) unless told otherwise
      Simulation sim(def);
      const int cols = cells + 2, frames = 480, averaged = 120;
      double drop = 0.0;
      for (int f = 0; f < frames; ++f) {
        ASSERT_TRUE(sim.step());
        if (f < frames - averaged) continue;
        double tip = 0.0;
        for (int r = 0; r < 4; ++r) tip += sim.state().x[sim.model().index(cols - 1, r)].y();
        drop += (1.0 - tip / 4.0) / averaged;
      }
      std::printf(
          "elastica %s %s L=%.3f %d cells, %d substeps: tip drop %.5f m, shooting %.5f m "
          "(%+.2f%%), kinetic energy at 8 s %.3g J\n",
          to_string(method), preset, L, cells, sim.substeps_per_frame(), drop, expected,
          100.0 * (drop / expected - 1.0), sim.diagnostics().kinetic_energy);
      EXPECT_NEAR(drop / expected, 1.0, 0.05) << to_string(method) << " " << preset << " " << cells;
    }
}

INSTANTIATE_TEST_SUITE_P(StiffAndSoft, Elastica,
                         ::testing::Values(StripCase{"cotton-polyester", 0.08},
                                           StripCase{"knit", 0.05}),
                         [](const auto& test) {
                           return std::string(test.param.preset[0] == 'k' ? "knit" : "stiff");
                         });

}  // namespace
}  // namespace drape
