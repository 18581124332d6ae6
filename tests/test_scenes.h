// Scenes several test files share: the shipped ones, the benchmark's and a bare cloth.
#pragma once

#include <string>

#include "drape/scene.h"
#include "io/scene_io.h"

namespace drape::testing_support {

/// A scene from scenes/, as shipped.
inline SceneDef shipped(const std::string& name) {
  return io::load_scene(std::string(DRAPE_SOURCE_DIR) + "/scenes/" + name + ".json");
}

/// A scene from bench/scenes/ (the standard benchmark's cloth), as shipped.
inline SceneDef bench_scene(const std::string& name) {
  return io::load_scene(std::string(DRAPE_SOURCE_DIR) + "/bench/scenes/" + name + ".json");
}

/// A cloth with nothing but what a test turns on: no gravity, drag, wind, pins or perturbation.
inline SceneDef bare(Method method = Method::symplectic) {
  SceneDef def;
  def.cloth.cols = def.cloth.rows = 8;
  def.cloth.pins.clear();
  def.cloth.perturbation = 0.0;
  def.forces.gravity = Vec3::Zero();
  def.forces.air_drag = 0.0;
  def.solver.method = method;
  return def;
}

}  // namespace drape::testing_support
