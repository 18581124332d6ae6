// The material presets. Density, stretch, shear and bending are the measurements of Wang,
// O'Brien & Ramamoorthi 2011 ("Data-driven elastic models for cloth: modeling and measurement",
// SIGGRAPH), from the material files distributed with ARCSim (Berkeley Garment Library): the
// density; the first (smallest-strain) sample of the piecewise-linear stretching data, C11 and
// C22 as stretch [warp, weft] and C33 as shear; the first (smallest-curvature) sample of the
// bending data at 0° and 90° as bending [warp, weft]. compression and damping are not
// measured: they are drape's choice, the same for every preset. The README lists the sources.
#include <array>

#include "drape/material.h"

namespace drape {

namespace {

struct Preset {
  const char* name;
  double density;          // kg/m²
  double stretch[2];       // N/m
  double shear;            // N/m
  double bending[2];       // N·m
};

// Wang et al. 2011's sample names in the comments.
constexpr std::array<Preset, 4> kPresets{{
    // "11oz black denim", 99% cotton 1% spandex (jeans).
    {"denim", 0.324, {205.352005, 1013.88629}, 53.387184, {64.196457e-6, 96.951576e-6}},
    // "gray interlock", 60% cotton 40% polyester knit (t-shirt).
    {"knit", 0.187, {16.593832, 34.477123}, 36.860302, {23.191698e-6, 14.267624e-6}},
    // "white dots on black", 100% polyester (tablecloth).
    {"polyester", 0.128, {2002.08618, 2027.48559}, 19.189022, {51.713814e-6, 31.282822e-6}},
    // "royal target", 65% cotton 35% polyester (pants).
    {"cotton-polyester", 0.220, {2016.55456, 2034.97644}, 104.759674,
     {125.409805e-6, 125.409805e-6}},
}};

}  // namespace

std::optional<MaterialDef> material_preset(const std::string& name) {
  for (const Preset& p : kPresets) {
    if (name != p.name) continue;
    MaterialDef m;
    m.name = p.name;
    m.density = p.density;
    m.stretch = Vec2(p.stretch[0], p.stretch[1]);
    m.shear = p.shear;
    m.bending = Vec2(p.bending[0], p.bending[1]);
    return m;
  }
  return std::nullopt;
}

std::vector<std::string> material_preset_names() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

}  // namespace drape
