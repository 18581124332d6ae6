// The fabric lab (issue 22): the elastica it compares with against the small-deflection closed
// form and Peirce's formula; the cantilever test on simulated strips against the elastica; the
// Cusick measurement on shapes whose shadow is known; and simulated drapes that behave as the
// textile literature says (stiffer drapes less; 4 to 10 folds).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "drape/error.h"
#include "drape/material.h"
#include "io/scene_io.h"
#include "lab/cantilever.h"
#include "lab/cusick.h"
#include "lab/elastica.h"

namespace drape {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ElasticaSolution, SmallDeflectionIsTheBeamsWLToTheFourthOverEightB) {
  // A uniformly loaded cantilever bends wL⁴/(8B) at its tip while the slope stays small.
  const double B = 1e-2, w = 1.0, L = 0.05;  // the tip drops 0.16% of L
  const lab::StripTip t = lab::elastica_tip(B, w, L);
  const double beam = w * std::pow(L, 4) / (8.0 * B);
  EXPECT_NEAR(t.drop / beam, 1.0, 1e-3);
  EXPECT_NEAR(t.along, L, 1e-4 * L);  // hardly shortened
}

TEST(ElasticaSolution, PeircesBendingLengthIsHalfTheOverhangAt41Point5Degrees) {
  // Peirce's formula c = l·(cos(θ/2)/(8 tan θ))^(1/3) is 0.4996·l at 41.5°: the test's angle
  // was chosen so; the exact elastica agrees within a percent.
  for (double B : {20e-6, 64e-6, 125e-6}) {
    const double w = 0.25 * 9.81, c = std::cbrt(B / w);
    const double l = lab::elastica_overhang(B, w, 41.5 * kPi / 180.0);
    EXPECT_NEAR(0.5 * l / c, 1.0, 0.01) << B;
    const lab::StripTip t = lab::elastica_tip(B, w, l);
    EXPECT_NEAR(std::atan2(t.drop, t.along) * 180.0 / kPi, 41.5, 1e-3);
  }
}

SceneDef cantilever(const std::string& preset, int cells) {
  return io::parse_scene(lab::cantilever_scene(io::material_json(*material_preset(preset)), cells),
                         "test");
}

TEST(LabCantilever, MeasuresTheMaterialsRigidityOnAStiffAndASoftPreset) {
  // The strip slides out until its tip meets the 41.5° plane: the overhang is the elastica's,
  // and ρg·(overhang/2)³ the material's B, within the test's 5%. Every overhang comes to rest,
  // at the command's default 80 cells too (with CG stopping at 1e-5, not tight enough to
  // resolve the 0.1 mm/s the rest test asks for, its last six overhangs never did).
  for (const auto& [preset, cells] : {std::pair{"denim", 40}, {"knit", 40}, {"denim", 80}}) {
    const lab::CantileverResult r = lab::run_cantilever(cantilever(preset, cells));
    ASSERT_TRUE(r.reached) << preset;
    std::printf(
        "cantilever %s, %d cells: overhang %.4f m (elastica %.4f), B %.3g N·m "
        "(material %.3g), %zu stages\n",
        preset, cells, r.overhang, r.elastica_overhang, r.rigidity, r.material_rigidity,
        r.stages.size());
    EXPECT_NEAR(r.overhang / r.elastica_overhang, 1.0, 0.02) << preset;
    EXPECT_NEAR(r.rigidity / r.material_rigidity, 1.0, 0.05) << preset;
    EXPECT_DOUBLE_EQ(r.bending_length, 0.5 * r.overhang);
    for (const lab::CantileverStage& s : r.stages) EXPECT_TRUE(s.at_rest) << s.overhang;
    // Each overhang hangs lower than the one before.
    for (size_t k = 1; k < r.stages.size(); ++k)
      EXPECT_GT(r.stages[k].angle, r.stages[k - 1].angle);
  }
}

TEST(LabCantilever, RefusesASceneThatIsNotTheTest) {
  SceneDef def = cantilever("denim", 20);
  def.cloth.material.reset();
  EXPECT_THROW(lab::run_cantilever(def), InputError);
  def = cantilever("denim", 20);
  def.cloth.pins.clear();
  EXPECT_THROW(lab::run_cantilever(def), InputError);
}

// Both tests stop when their stop flag goes up (Ctrl-C or SIGTERM in `drape lab`), with the
// lab's own method, implicit at one substep a frame: a frame it starts it finishes, so the
// stop must be seen between frames. (Before, the cantilever went on to its end: at 160 cells,
// past a quarter of an hour after SIGTERM.)
TEST(LabStop, BothTestsStopWithinAFrameOfTheFlag) {
  std::atomic<bool> stop{false};
  int frames = 0;
  const lab::CantileverResult c =
      lab::run_cantilever(cantilever("knit", 20), {}, &stop);  // a run to compare: it measures
  EXPECT_TRUE(c.reached);
  EXPECT_FALSE(c.stopped);
  stop = true;
  const lab::CantileverResult s = lab::run_cantilever(cantilever("knit", 20), {}, &stop);
  EXPECT_TRUE(s.stopped);
  EXPECT_FALSE(s.reached);
  EXPECT_TRUE(s.stages.empty());

  SceneDef def =
      io::parse_scene(lab::cusick_scene(io::material_json(*material_preset("knit"))), "test");
  lab::use_cusick_specimen(def, 8);
  const lab::CusickResult r = lab::run_cusick(
      def, 8.0, [&](int done, int) { frames = done; }, &stop);
  EXPECT_TRUE(r.stopped);
  EXPECT_LE(r.frames, 1);
  EXPECT_LE(frames, 1);
}

// A flat disc of the specimen's radius, shaped radially: every point at radius r > the
// pedestal's goes to radius `outline(r, angle)` (level), so the shadow is known.
template <typename Outline>
lab::CusickMeasure measure_shaped(Outline outline) {
  SceneDef def;
  lab::use_cusick_specimen(def, 40);
  std::vector<Vec3> x = def.cloth.mesh->positions;
  for (Vec3& p : x) {
    const double r = std::hypot(p.x(), p.z()), a = std::atan2(p.z(), p.x());
    if (r <= lab::kPedestalRadius) continue;
    const double to = outline(r, a);
    p.x() = to * std::cos(a);
    p.z() = to * std::sin(a);
  }
  return lab::measure_cusick(x, def.cloth.mesh->triangles);
}

TEST(LabCusick, AFlatDiscIsAHundredPercentAndAHangingOneZero) {
  const lab::CusickMeasure flat = measure_shaped([](double r, double) { return r; });
  // The disc's mesh is a polygon inside the circle: a little less than its area.
  EXPECT_NEAR(flat.drape_coefficient, 100.0, 1.0);
  EXPECT_EQ(flat.folds, 0);
  const lab::CusickMeasure hanging =
      measure_shaped([](double, double) { return lab::kPedestalRadius; });
  EXPECT_NEAR(hanging.drape_coefficient, 0.0, 1.0);
  EXPECT_EQ(hanging.folds, 0);
}

TEST(LabCusick, ShadowAreaAndFoldsOfALobedOutline) {
  // r → p + (r − p)·(0.6 + 0.25·cos(n·a)): the outline p + 0.06·(0.6 + 0.25 cos n·a), whose
  // area ½∫R² da is known in closed form.
  const double p = lab::kPedestalRadius, d = lab::kSpecimenRadius - p;
  for (int n : {4, 7, 10}) {
    const lab::CusickMeasure m = measure_shaped(
        [&](double r, double a) { return p + (r - p) * (0.6 + 0.25 * std::cos(n * a)); });
    const double mean = p + 0.6 * d, amp = 0.25 * d;
    const double area = kPi * (mean * mean + 0.5 * amp * amp);
    EXPECT_NEAR(m.area / area, 1.0, 0.01) << n;
    EXPECT_EQ(m.folds, n);
    const double dc = 100.0 * (area - kPi * p * p) / (kPi * (p + d) * (p + d) - kPi * p * p);
    EXPECT_NEAR(m.drape_coefficient, dc, 1.0) << n;
  }
}

lab::CusickResult drape(const MaterialDef& m, int rings = 16,
                        std::optional<Method> method = std::nullopt) {
  SceneDef def = io::parse_scene(lab::cusick_scene(io::material_json(m)), "test");
  lab::use_cusick_specimen(def, rings);
  if (method) def.solver.method = *method;
  return lab::run_cusick(def, 8.0);
}

// The drape is the material's, not the method's: `fast` drapes denim as `implicit` does, and
// comes to rest. (Its springs damped the move across them too, by β times the stretch's
// stiffness, until 2026-12-07: the disc stood nearly flat and still moving after 8 s, DC 95%.)
TEST(LabCusick, FastDrapesDenimAsImplicitDoes) {
  const MaterialDef denim = *material_preset("denim");
  const lab::CusickResult implicit = drape(denim, 16, Method::implicit);
  const lab::CusickResult fast = drape(denim, 16, Method::fast);
  std::printf(
      "cusick denim, 16 rings: implicit DC %.1f%% (%d folds, %.2f s), fast %.1f%% (%d, "
      "%.2f s)\n",
      implicit.measure.drape_coefficient, implicit.measure.folds, implicit.frames / 60.0,
      fast.measure.drape_coefficient, fast.measure.folds, fast.frames / 60.0);
  ASSERT_TRUE(implicit.at_rest);
  EXPECT_TRUE(fast.at_rest);
  EXPECT_NEAR(fast.measure.drape_coefficient, implicit.measure.drape_coefficient, 1.0);
  EXPECT_EQ(fast.measure.folds, implicit.measure.folds);
}

TEST(LabCusick, StifferDrapesLessAndEveryPresetFoldsAsFabricsDo) {
  // The same denim with its bending rigidity quartered and quadrupled: a stiffer disc stands
  // out further.
  MaterialDef denim = *material_preset("denim");
  double before = -1.0;
  for (double scale : {0.25, 1.0, 4.0}) {
    MaterialDef m = denim;
    m.bending *= scale;
    const lab::CusickResult r = drape(m);
    std::printf("cusick denim B×%.2f: DC %.1f%%, %d folds, %.2f s\n", scale,
                r.measure.drape_coefficient, r.measure.folds, r.frames / 60.0);
    EXPECT_GT(r.measure.drape_coefficient, before + 5.0) << scale;
    before = r.measure.drape_coefficient;
  }
  // Real fabrics show 4 to 10 folds on the 18 cm pedestal.
  for (const std::string& name : material_preset_names()) {
    const lab::CusickResult r = drape(*material_preset(name));
    std::printf("cusick %s: DC %.1f%%, %d folds\n", name.c_str(), r.measure.drape_coefficient,
                r.measure.folds);
    EXPECT_GE(r.measure.folds, 4) << name;
    EXPECT_LE(r.measure.folds, 10) << name;
    EXPECT_GT(r.measure.drape_coefficient, 0.0) << name;
    EXPECT_LT(r.measure.drape_coefficient, 100.0) << name;
  }
}

// The drape coefficient settles as the disc is refined: denim at 32 rings and at the lab's
// default 40 agree within 2 points (measured 81.1% and 81.9%; at 16 and 24 rings it lay 8 and 3
// points below, so the check can fail).
TEST(LabCusick, TheDrapeCoefficientSettlesAsTheDiscIsRefined) {
  const MaterialDef denim = *material_preset("denim");
  const lab::CusickResult coarse = drape(denim, 32), fine = drape(denim, lab::kCusickRings);
  std::printf("cusick denim: DC %.1f%% at 32 rings, %.1f%% at %d\n",
              coarse.measure.drape_coefficient, fine.measure.drape_coefficient, lab::kCusickRings);
  EXPECT_NEAR(coarse.measure.drape_coefficient, fine.measure.drape_coefficient, 2.0);
}

}  // namespace
}  // namespace drape
