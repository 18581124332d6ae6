#include "lab/cantilever.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "drape/error.h"
#include "drape/simulation.h"
#include "lab/elastica.h"
#include "lab/settle.h"

namespace drape::lab {

namespace {

constexpr double kLength = 0.20;  // m, ASTM D1388's strip: 200 mm by 25 mm
constexpr double kWidth = 0.025;
constexpr double kHeight = 0.5;  // m, the platform's top

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

}  // namespace

nlohmann::json cantilever_scene(const nlohmann::json& material, int cells) {
  const double dx = kLength / cells;
  const int across = std::max(2, static_cast<int>(std::lround(kWidth / dx)));
  // The platform holds every column but the last two; its box reaches a quarter cell past the
  // last of them so that rounding cannot drop it.
  const double edge = kLength - 2.0 * dx;
  return {{"name", "cantilever"},
          {"cloth",
           {{"size", {kLength, kWidth}},
            {"resolution", {cells + 1, across + 1}},
            {"origin", {0.0, kHeight, 0.0}},
            {"orientation", "horizontal"},
            {"material", material},
            {"perturbation", 0.0},
            {"pins",
             {{{"box",
                {{"min", {-1.0, kHeight - 0.01, -1.0}},
                 {"max", {edge + 0.25 * dx, kHeight + 0.01, 1.0}}}}}}}}},
          {"forces",
           {{"gravity", {0.0, -9.81, 0.0}}, {"air_density", 1.225}, {"drag_coefficient", 1.2}}},
          // CG at its default 1e-5 leaves velocity errors above the 0.1 mm/s the rest test asks
          // for once the strip bends far: at 80 cells the last six overhangs never rested (600
          // frames each, 35 s in all); at 1e-7 all rest, in 795 frames and 13.8 s.
          {"solver", {{"method", "implicit"}, {"dt", 1.0 / 60.0}, {"cg_tolerance", 1e-7}}},
          {"duration", 60.0}};
}

CantileverResult run_cantilever(const SceneDef& def, const CantileverProgress& progress,
                                const std::atomic<bool>* stop) {
  if (!def.cloth.material)
    throw InputError("cloth.material", "missing: the cantilever test measures a material");
  if (def.cloth.mesh) throw InputError("cloth.mesh", "the cantilever test's strip is a grid");
  Simulation sim(def);
  sim.set_stop_flag(stop);
  const ClothModel& m = sim.model();
  const int cols = m.grid.cols, rows = m.grid.rows;
  auto column_pinned = [&](int c) {
    for (int r = 0; r < rows; ++r)
      if (!sim.state().pinned[m.index(c, r)]) return false;
    return true;
  };
  // The platform's edge: the last of the leading columns that are pinned whole.
  int edge = -1;
  while (edge + 1 < cols && column_pinned(edge + 1)) ++edge;
  if (edge < 1)
    throw InputError("cloth.pins", "must hold at least the strip's first two columns whole");
  if (edge >= cols - 1) throw InputError("cloth.pins", "hold the whole strip: nothing overhangs");

  CantileverResult out;
  const MaterialDef& mat = *def.cloth.material;
  out.weight = mat.density * def.forces.gravity.norm();
  out.material_rigidity = mat.bending.x();
  out.material_bending_length = std::cbrt(out.material_rigidity / out.weight);
  const double target = kCantileverAngle * std::numbers::pi / 180.0;
  out.elastica_overhang = elastica_overhang(out.material_rigidity, out.weight, target);

  const double dx = (m.rest_position[m.index(1, 0)] - m.rest_position[m.index(0, 0)]).norm();
  while (true) {
    // At rest: no particle moves faster than 0.1 mm/s (2 µm a frame).
    const Settled s = settle(sim, 1e-4, 10, 600);
    if (s.failed) {
      record_failure(sim, out);
      return out;
    }
    // Bending couples the last pinned segment with the first free one: the strip is held level
    // to the middle of the last pinned segment, which is where the elastica's clamp is (the
    // elastica test finds the same), and where the overhang is measured from.
    const Vec3 clamp =
        0.5 * (m.rest_position[m.index(edge - 1, 0)] + m.rest_position[m.index(edge, 0)]);
    Vec3 tip = Vec3::Zero();
    for (int r = 0; r < rows; ++r) tip += sim.state().x[m.index(cols - 1, r)];
    tip /= rows;
    CantileverStage stage;
    stage.overhang = (cols - 1 - edge + 0.5) * dx;
    stage.angle = degrees(std::atan2(clamp.y() - tip.y(), tip.x() - clamp.x()));
    stage.frames = s.frames;
    stage.at_rest = s.at_rest;
    out.stages.push_back(stage);
    if (progress) progress(stage, edge - 1);
    if (stage.angle >= kCantileverAngle) {
      out.reached = true;
      if (out.stages.size() == 1)
        out.message =
            "the first overhang already reaches the plane: the result is "
            "interpolated from a flat strip; give more cells";
      const CantileverStage before =
          out.stages.size() > 1 ? out.stages[out.stages.size() - 2] : CantileverStage{};
      const double t = (kCantileverAngle - before.angle) / (stage.angle - before.angle);
      out.overhang = before.overhang + t * (stage.overhang - before.overhang);
      out.bending_length = 0.5 * out.overhang;
      out.rigidity = out.weight * std::pow(out.bending_length, 3);
      return out;
    }
    if (edge == 1) return out;  // the strip ran out before its tip reached the plane
    // The strip slides a column further over the edge: the edge moves back one column.
    for (int r = 0; r < rows; ++r) sim.set_pinned(m.index(edge, r), false);
    --edge;
  }
}

}  // namespace drape::lab
