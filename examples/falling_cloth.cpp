// A minimal program on libdrape: a cloth let go in free fall, stepped for half a second, its fall
// compared with ½·g·t². Built against an installed drape by CMake (CMakeLists.txt here) and by
// pkg-config (see the README, "Using the library").
#include <cmath>
#include <cstdio>

#include "drape/simulation.h"

int main() {
  drape::SceneDef def;  // documented defaults: the `hang` scene
  def.cloth.cols = def.cloth.rows = 16;
  def.cloth.pins.clear();        // nothing holds it
  def.cloth.perturbation = 0.0;  // exactly flat, so its springs stay at their rest length
  def.forces.air_drag = 0.0;     // and nothing slows it: free fall
  drape::Simulation sim(def);    // throws drape::InputError on bad input

  const double start = sim.state().x[0].y();
  for (int frame = 0; frame < 30; ++frame) sim.step();

  // Semi-implicit Euler at substep h falls ½·g·t² + ½·g·h·t: the closed form plus its
  // first-order error.
  const double g = -def.forces.gravity.y(), t = sim.time();
  const double h = def.solver.dt / sim.substeps_per_frame();
  const double fell = start - sim.state().x[0].y();
  const double closed_form = 0.5 * g * t * t, bound = 0.5 * g * h * t;
  std::printf(
      "a %dx%d cloth fell %.6f m in %.4f s; 1/2 g t^2 = %.6f m; difference %.3g m, "
      "within 1/2 g h t = %.3g m at %d substeps per frame\n",
      def.cloth.cols, def.cloth.rows, fell, t, closed_form, fell - closed_form, bound,
      sim.substeps_per_frame());
  return std::abs(fell - closed_form) <= bound * (1.0 + 1e-6) ? 0 : 1;
}
