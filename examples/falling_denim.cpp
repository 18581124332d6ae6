// A fabric on libdrape: half a metre of 11 oz denim (a material preset, in physical units) let
// go flat, high above the ground, in sea-level air. It falls at the terminal speed of its
// material, where the air's drag on its area, ½·ρ·C·v², carries its weight per area ρ_A·g:
// v = sqrt(2·ρ_A·g / (ρ·C)), whatever the resolution. Nothing here sets the air: a cloth with a
// material feels the air by its area by default. Built as falling_cloth.cpp is.
#include <cmath>
#include <cstdio>

#include "drape/material.h"
#include "drape/simulation.h"

int main() {
  drape::SceneDef def;
  def.cloth.material = drape::material_preset("denim");  // 0.324 kg/m², its stiffness, bending
  def.cloth.width = def.cloth.height = 0.5;
  def.cloth.cols = def.cloth.rows = 16;
  def.cloth.orientation = drape::Orientation::horizontal;
  def.cloth.origin = drape::Vec3(0.0, 100.0, 0.0);
  def.cloth.pins.clear();
  def.cloth.perturbation = 0.0;  // flat: it falls broadside
  drape::Simulation sim(def);

  for (int frame = 0; frame < 180; ++frame) sim.step();
  double speed = 0.0;
  for (const drape::Vec3& v : sim.state().v) speed -= v.y() / sim.state().v.size();

  const double g = -def.forces.gravity.y(), density = def.cloth.material->density;
  const double rho = def.forces.air_density_for(true), c = def.forces.drag_coefficient;
  const double terminal = std::sqrt(2.0 * density * g / (rho * c));
  // The step takes the drag after gravity's kick, so its fixed point lies h·g/2 below (first
  // order in the substep h): v·(1 + h·k·(v + h·g)) = v + h·g with k = ρ·C / (2·ρ_A).
  const double h = def.solver.dt / sim.substeps_per_frame(), k = 0.5 * rho * c / density;
  const double stepped = 0.5 * (-h * g + std::sqrt(h * h * g * g + 4.0 * g / k));
  std::printf(
      "denim falling flat after %.1f s: %.4f m/s; terminal speed sqrt(2 rho_A g / (rho C)) = "
      "%.4f m/s, %.4f m/s at the solver's step (%d substeps per frame)\n",
      sim.time(), speed, terminal, stepped, sim.substeps_per_frame());
  return std::abs(speed / stepped - 1.0) < 1e-3 ? 0 : 1;
}
