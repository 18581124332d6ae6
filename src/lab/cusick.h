// The Cusick drape test (BS 5058, ISO 9073-9): a disc of fabric 30 cm across clamped on a
// pedestal 18 cm across hangs in folds; the area of its shadow from above gives the drape
// coefficient DC% = (S − S_pedestal)/(S_specimen − S_pedestal)·100 (100%: a rigid disc, 0%: a
// limp one hanging straight down), and the shadow's outline the number of folds.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "drape/mesh.h"
#include "drape/scene.h"

namespace drape::lab {

inline constexpr double kSpecimenRadius = 0.15;  ///< m
inline constexpr double kPedestalRadius = 0.09;  ///< m
inline constexpr double kPedestalHeight = 0.2;   ///< m, where the specimen is clamped

/// The test's scene without its cloth's shape: `material` (as cloth.material holds it) clamped
/// by a ball pin of the pedestal's radius at its centre, on a thin column (a capsule).
/// Overrides apply to this JSON; then use_cusick_specimen gives the cloth its disc.
nlohmann::json cusick_scene(const nlohmann::json& material);

/// Makes the cloth of `def` the specimen: a disc of kSpecimenRadius, `rings` rings of
/// irregular triangles (shapes::disc), level at the pedestal's top.
void use_cusick_specimen(SceneDef& def, int rings);

/// The rings `drape lab cusick` takes by default: from 32 rings on the drape coefficient moves
/// by a few points at most as the mesh is refined, and at 40 every preset's lies within a
/// point of its value at 64 rings (README, Fabric lab); at 24 it lay 3 to 6 points below.
inline constexpr int kCusickRings = 40;

/// A top view of the cloth: which pixels its triangles cover (its shadow under light from
/// above), `size` pixels across a square `width` metres wide centred on the pedestal.
struct Shadow {
  int size = 0;
  double width = 0.0;
  std::vector<uint8_t> covered;  ///< size × size, rows along +z, 1 where covered
  double pixel() const { return width / size; }
};

struct CusickMeasure {
  double area = 0.0;               ///< m², the shadow's
  double drape_coefficient = 0.0;  ///< %, DC
  int folds = 0;                   ///< outward lobes of the shadow's outline
  /// m, the outline's distance from the centre at each degree (0 at +x, 90 at +z), smoothed
  /// over ±3°
  std::vector<double> hem;
  Shadow shadow;
};

/// The shadow of a cloth from above on `pixels`² pixels over a square `width` metres wide
/// centred on the y axis: a pixel is covered when its centre lies inside a triangle's projection.
Shadow cast_shadow(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles, double width,
                   int pixels);
double covered_area(const Shadow& s);  ///< m²

/// Measures a cloth's shadow about the pedestal's axis (x = z = 0).
CusickMeasure measure_cusick(const std::vector<Vec3>& x, const std::vector<Triangle>& triangles);

struct CusickResult {
  CusickMeasure measure;
  int frames = 0;               ///< frames simulated before measuring
  bool at_rest = false;         ///< the cloth came to rest in the frames allowed
  bool stopped = false;         ///< interrupted (stop flag)
  bool diverged = false;        ///< the simulation blew up; `message` says why
  int64_t diverged_frame = -1;  ///< the frame it blew up at
  std::string message;
};

/// Called after each frame with the frames done and the most allowed.
using CusickProgress = std::function<void(int frame, int most)>;

/// Drapes the specimen until it comes to rest (at most `seconds`), then measures it.
CusickResult run_cusick(const SceneDef& def, double seconds, const CusickProgress& progress = {},
                        const std::atomic<bool>* stop = nullptr);

/// The shadow as an RGBA picture (top row first): the shadow dark on white, the pedestal
/// lighter inside it, the flat specimen's circle and the outline traced.
std::vector<uint8_t> shadow_picture(const CusickMeasure& m);

}  // namespace drape::lab
