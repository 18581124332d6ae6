// The methods every method-wide test runs: each method in double, xpbd in single too, xpbd
// with its structural springs solved as chains (solver.line_passes), and auto.
#pragma once

#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "drape/scene.h"
#include "drape/simulation.h"

namespace drape::testing_support {

/// A method and the precision it steps in, and xpbd's line passes.
struct Variant {
  Method method;
  Precision precision = Precision::f64;
  int line_passes = 0;
};
inline const Variant kVariants[] = {{Method::symplectic},
                                    {Method::implicit},
                                    {Method::xpbd},
                                    {Method::fast},
                                    {Method::xpbd, Precision::f32},
                                    {Method::xpbd, Precision::f64, 3},
                                    {Method::automatic}};

inline std::string variant_name(const ::testing::TestParamInfo<Variant>& p) {
  return std::string(to_string(p.param.method)) +
         (p.param.precision == Precision::f32 ? "_single" : "") +
         (p.param.line_passes > 0 ? "_lines" : "");
}

/// `def` stepped by variant v.
inline SceneDef with(SceneDef def, const Variant& v) {
  def.solver.method = v.method;
  def.solver.precision = v.precision;
  def.solver.line_passes = v.line_passes;
  return def;
}

/// Whether the variant steps in single precision (auto chooses it).
inline bool single(const Variant& v) {
  return v.precision == Precision::f32 || v.method == Method::automatic;
}

/// The cloth's momentum Σ m·v (kg·m/s).
inline Vec3 momentum(const Simulation& sim) {
  Vec3 p = Vec3::Zero();
  for (int32_t i = 0; i < sim.model().size(); ++i) p += sim.model().mass[i] * sim.state().v[i];
  return p;
}

/// How far the momentum of a cloth with no external force may drift under variant v over
/// `frames` frames of `substeps` substeps, relative to 1 + |p₀|: float round-off each substep;
/// in double, what the iterative solves leave (implicit's CG at 1e-10, fast's iterations), and
/// round-off for the exact updates.
inline double momentum_allowance(const Variant& v, int frames, int substeps) {
  return single(v) ? frames * substeps * double(std::numeric_limits<float>::epsilon())
         : v.method == Method::implicit ? 1e-8
         : v.method == Method::fast     ? 1e-9
                                        : 1e-12;
}

}  // namespace drape::testing_support
