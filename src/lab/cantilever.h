// The cantilever bending test (Peirce 1930; ASTM D1388): a strip of fabric slides over the edge
// of a level platform until its tip meets a plane through the edge inclined 41.5° below the
// horizontal. Half the overhang is the bending length c, and ρ·g·c³ the flexural rigidity.
// Here the strip is a grid of the material, held level (pinned) on the platform; the edge moves
// back a column at a time, and the cloth comes to rest at each overhang before the next.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/scene.h"

namespace drape::lab {

inline constexpr double kCantileverAngle = 41.5;  ///< degrees below the horizontal (ASTM D1388)

/// The test's scene: a strip 20 cm by 2.5 cm of `material` (as cloth.material holds it) along
/// the warp, `cells` cells along its length, lying level at y = 0.5 m from x = 0 with all but
/// its last two cells on the platform (pinned by a box). Overrides apply to this JSON.
nlohmann::json cantilever_scene(const nlohmann::json& material, int cells);

/// One overhang the strip came to rest at.
struct CantileverStage {
  double overhang = 0.0;  ///< m, from the edge to the strip's end, along the strip
  double angle = 0.0;     ///< degrees, of the line from the edge to the tip, below horizontal
  int frames = 0;         ///< frames it took to come to rest (or the most allowed)
  bool at_rest = false;   ///< it came to rest within the frames allowed
};

struct CantileverResult {
  bool reached = false;                  ///< the tip reached the plane before the strip ran out
  double overhang = 0.0;                 ///< m, where it did (interpolated between two stages)
  double bending_length = 0.0;           ///< m, c = overhang / 2
  double rigidity = 0.0;                 ///< N·m, ρ·g·c³ (per width)
  double weight = 0.0;                   ///< N/m², ρ·g of the material
  double material_rigidity = 0.0;        ///< N·m, the material's own B along the strip
  double material_bending_length = 0.0;  ///< m, (B/(ρ·g))^(1/3)
  /// m, the overhang at which the exact elastica of the material meets the plane (Peirce's
  /// c = overhang/2 is itself an approximation of it)
  double elastica_overhang = 0.0;
  std::vector<CantileverStage> stages;
  bool stopped = false;         ///< interrupted (stop flag)
  bool diverged = false;        ///< the simulation blew up; `message` says why
  int64_t diverged_frame = -1;  ///< the frame it blew up at
  std::string message;
};

/// Called after each stage with the stages so far and the columns left to release.
using CantileverProgress = std::function<void(const CantileverStage&, int left)>;

/// Runs the test on a scene made by cantilever_scene (overridden as the user asked): a grid
/// with a material, the strip along +x, its platform part pinned. Throws InputError for a
/// scene that is not one (no material, not a grid, no pinned column, nothing overhanging).
CantileverResult run_cantilever(const SceneDef& def, const CantileverProgress& progress = {},
                                const std::atomic<bool>* stop = nullptr);

}  // namespace drape::lab
