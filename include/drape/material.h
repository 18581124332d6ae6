// A fabric in physical units: what `cloth.material` holds, and the presets with their sources.
// With a material every particle's mass and every spring's and bending element's stiffness
// derive from it and the mesh, so that one material behaves alike at any resolution.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "drape/math.h"

namespace drape {

/// Warp runs along the texture's u (a grid's columns, +x), weft along v (its rows).
struct MaterialDef {
  std::string name;  ///< the preset it came from, or empty for numbers given in full
  double density = 0.2;  ///< kg/m², mass per area
  /// N/m, the sheet's tensile stiffness (force per width per strain) along warp and weft, with
  /// the cross direction held
  Vec2 stretch{1000.0, 1000.0};
  double shear = 50.0;  ///< N/m, in-plane shear stiffness (force per width per radian)
  Vec2 bending{20e-6, 20e-6};  ///< N·m, flexural rigidity B of a warp and a weft strip
  /// Fraction of the tensile stiffness a compressed thread resists with, in [0, 1]; low values
  /// let compressed cloth buckle out of its plane (Choi & Ko 2002)
  double compression = 0.1;
  /// s, stiffness-proportional (Rayleigh) damping β: each stretch, shear and bending term's
  /// damping is β times its stiffness, so damping scales with the material, not the mesh
  double damping = 0.002;
};

/// The preset called `name` ("denim", "knit", ...), if there is one.
std::optional<MaterialDef> material_preset(const std::string& name);
/// Every preset's name, in the order the README lists them.
std::vector<std::string> material_preset_names();

}  // namespace drape
