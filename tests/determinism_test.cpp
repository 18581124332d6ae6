// Determinism: the same scene, method and thread count give bit-identical states (hashed);
// and, because springs are summed colour by colour and per-particle loops only gather, the
// thread count does not change the bits either.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "drape/error.h"
#include "drape/simulation.h"
#include "io/scene_io.h"
#include "shipped_scenes.h"
#include "test_scenes.h"

namespace drape {
namespace {

using testing_support::shipped;

// FNV-1a over the bytes of every position, velocity, normal and area.
uint64_t state_hash(const ClothState& s) {
  uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](const auto& values) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (size_t k = 0; k < values.size() * sizeof(values[0]); ++k)
      h = (h ^ bytes[k]) * 1099511628211ULL;
  };
  mix(s.x);
  mix(s.v);
  mix(s.normal);
  mix(s.area);
  return h;
}

uint64_t run(SceneDef def, int frames) {
  Simulation sim(def);
  for (int f = 0; f < frames; ++f) EXPECT_TRUE(sim.step()) << sim.divergence();
  return state_hash(sim.state());
}

TEST(Determinism, EachShippedSceneAndMethodHashesTheSameTwice) {
  for (const std::string& name : testing_support::shipped_scene_names()) {
    for (Method method : kAllMethods) {
      SceneDef def = shipped(name);
      def.solver.method = method;
      if (method == Method::symplectic) {
        // A stiff material on fine cells needs more explicit substeps than max_substeps allows
        // (cusick: about 18,000 a frame): refused, naming solver.substeps; nothing to hash.
        try {
          Simulation probe(def);
        } catch (const InputError& e) {
          EXPECT_EQ(e.path(), "solver.substeps") << name << ": " << e.what();
          continue;
        }
      }
      const uint64_t first = run(def, 20), second = run(def, 20);
      EXPECT_EQ(first, second) << name << " " << to_string(method);
    }
  }
}

TEST(Determinism, TheThreadCountDoesNotChangeTheBits) {
#ifndef _OPENMP
  GTEST_SKIP() << "built without OpenMP: one thread only";
#else
  // 96×96 = 9216 particles: above the size at which loops go parallel (src/core/parallel.h).
  SceneDef def = shipped("wind");
  def.cloth.cols = def.cloth.rows = 96;
  def.cloth.mass = 100.0;  // heavy, so a few substeps are stable and the test stays quick
  def.solver.method = Method::symplectic;
  def.solver.substeps = 20;
  const int before = omp_get_max_threads();
  // The seed's method, then xpbd (its grid sweeps with stiff sweeps, and line passes with
  // attachments and stiff sweeps after them) in both precisions, then auto (which the default
  // thread count's choice, app/thread_chooser.h, relies on), then xpbd with a material.
  for (Precision precision : {Precision::f64, Precision::f32}) {
    for (int variant = 0; variant < 4; ++variant) {
      const bool xpbd = variant == 1 || variant == 2, lines = variant == 2;
      if (!xpbd && precision == Precision::f32) continue;
      SceneDef d = def;
      if (variant == 3) d.solver.method = Method::automatic, d.solver.substeps = 0;
      if (xpbd) d.solver.method = Method::xpbd;
      if (xpbd) d.solver.stiff_sweeps = 2;
      if (lines) d.solver.line_passes = 2;
      if (lines) d.cloth.long_range.enabled = true;
      d.solver.precision = precision;
      const int frames = variant == 3 ? 40 : 3;  // auto decides every 10 frames
      omp_set_num_threads(1);
      const uint64_t one = run(d, frames);
      omp_set_num_threads(2);
      const uint64_t two = run(d, frames);
      EXPECT_EQ(one, two) << to_string(d.solver.method) << " " << to_string(precision)
                          << (lines ? " with line passes" : "");
    }
  }
  // xpbd with a material (the mesh solver on the grid: springs softened in compression, bending
  // elements in colours of their own, area drag, damping on the velocities), both precisions;
  // one frame is 75 substeps here.
  SceneDef denim = shipped("sphere-denim");
  denim.cloth.cols = denim.cloth.rows = 96;
  denim.solver.method = Method::xpbd;
  for (Precision precision : {Precision::f64, Precision::f32}) {
    denim.solver.precision = precision;
    omp_set_num_threads(1);
    const uint64_t one = run(denim, 1);
    omp_set_num_threads(2);
    const uint64_t two = run(denim, 1);
    EXPECT_EQ(one, two) << "xpbd with a material, " << to_string(precision);
  }
  omp_set_num_threads(before);
#endif
}

}  // namespace
}  // namespace drape
