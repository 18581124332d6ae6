// The methods every method-wide test runs: each method in double, xpbd in single too, xpbd
// with its structural springs solved as chains (solver.line_passes), and auto.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "drape/scene.h"

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

}  // namespace drape::testing_support
