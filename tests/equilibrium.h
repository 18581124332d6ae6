// The static-equilibrium check the grid and the mesh tests share: every method finds the rest
// shape the symplectic reference finds.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "drape/simulation.h"

namespace drape::testing_support {

/// Lets `def` (a cloth pinned at its corners, 1 m up, damped to settle within 12 s) come to
/// rest with symplectic, implicit, fast and xpbd (at 200 substeps: its one sweep per substep
/// converges slowly across the cloth), and expects every rest shape within 5% of the
/// reference's sag of the symplectic one.
inline void expect_every_method_rests_where_symplectic_does(const SceneDef& def) {
  auto rest_shape = [&](Method m, int substeps) {
    SceneDef d = def;
    d.solver.method = m;
    d.solver.substeps = substeps;
    Simulation sim(d);
    while (sim.time() < 12.0 - 1e-9) EXPECT_TRUE(sim.step()) << sim.divergence();
    EXPECT_LT(sim.diagnostics().kinetic_energy, 1e-4) << to_string(m);
    return sim.state().x;
  };
  const std::vector<Vec3> reference = rest_shape(Method::symplectic, 0);
  double peak_sag = 0.0;
  for (const Vec3& x : reference) peak_sag = std::max(peak_sag, 1.0 - x.y());
  ASSERT_GT(peak_sag, 0.05);
  for (auto [method, substeps] :
       {std::pair{Method::implicit, 0}, std::pair{Method::fast, 0}, std::pair{Method::xpbd, 200}}) {
    const std::vector<Vec3> x = rest_shape(method, substeps);
    double worst = 0.0;
    for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, (x[i] - reference[i]).norm());
    EXPECT_LE(worst, 0.05 * peak_sag) << to_string(method);
  }
}

}  // namespace drape::testing_support
