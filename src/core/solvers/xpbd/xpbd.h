// What the two xpbd solvers share beside their particles (particles.h): defaults, the rule for
// automatic substeps, and a spring's compliance for a substep.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "drape/error.h"
#include "solver.h"

namespace drape::xpbd {

inline constexpr int kDefaultIterations = 1;

// The stiff sweeps (solver.stiff_sweeps) resolve the contacts before every kContactEvery-th of
// them, starting with the first, so that the springs converge together with the contacts rather
// than against contacts resolved only at the substep's end. Without that, cloth folding off a
// collider keeps its structural springs compressed where it leaves the surface: drape-128 at 32
// substeps held 1.6% there with 10 sweeps and with 150. With it the bench meets its bar on
// drape-128 at 32 substeps + 20 sweeps, against 72 + 10 without. Every sweep, every second, third
// or fifth gave the same fewest substeps on the bench at 64² and 128²; a contact pass costs about
// half a stiff sweep, so every third keeps the gain for a third of the passes.
inline constexpr int kContactEvery = 3;

/// Substeps per frame when the scene leaves it to the method: with one iteration per substep a
/// spring reaches an effective stiffness of about min(k, m/h²), so the smallest count with
/// m/h² ≥ k for every spring that `swept(spring)` says is swept spring by spring (not solved as
/// a chain): below it, stiff and soft springs (stretch and bending) look alike and the cloth
/// acts like rubber. A material's bending element counts as a spring whose k·(1/m_i + 1/m_j)
/// is its k·Σ_k w_k²/m_k (see xpbd_bend). Throws InputError past solver.max_substeps.
template <class Swept>
int automatic_substeps(const World& w, const SolverDef& def, Swept swept) {
  const std::vector<double>& inv_mass = w.state.inv_mass;
  double kw = 0.0;
  for (const Spring& s : w.model.springs) {
    if (!swept(s)) continue;
    kw = std::max(kw, s.stiffness * std::max(inv_mass[s.i], inv_mass[s.j]));
  }
  for (const BendingElement& b : w.model.bending) {
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) sum += b.w[k] * b.w[k] * inv_mass[b.v[k]];
    kw = std::max(kw, 0.5 * b.stiffness * sum);
  }
  const double needed = std::ceil(def.dt * std::sqrt(kw));
  if (!(needed <= def.max_substeps)) {
    throw InputError("solver.substeps",
                     "the xpbd method needs " + count_text(needed) +
                         " substeps per frame to reach the springs' stiffness, more than "
                         "solver.max_substeps = " +
                         std::to_string(def.max_substeps) +
                         "; lower the stiffness, raise the mass, use a smaller dt, or fix "
                         "solver.substeps yourself (softer cloth)");
  }
  return std::max(1, static_cast<int>(needed));
}

/// Inside a solver's parallel region, before substep k of a frame of substeps h from w.time:
/// false where the frame stops here (a stop asked for ends it between whole substeps), else
/// true with moving colliders posed for the substep. `stopping` is shared by the threads, and
/// every thread gets the same answer.
inline bool substep_begins(World& w, int k, double h, bool& stopping) {
  if (k > 0 && w.stop) {
    // One thread asks; the barrier that ends `single` shows every thread its answer.
#pragma omp single
    stopping = w.stop_here();
    if (stopping) return false;
  }
  if (w.colliders_move()) {
    // One thread poses them; the barrier that ends `single` shows every thread the poses.
#pragma omp single
    w.pose_colliders(w.time + k * h, w.time + (k + 1) * h);
  }
  return true;
}

/// A spring's XPBD compliance α̃ = 1/(k·h²) and damping γ = α̃·β·h²/h = c/(k·h) with β = c
/// (N·s/m) for a substep of h (Macklin et al. 2016, eq. 26). Read into named locals, not a
/// structured binding: clang 14 cannot capture a structured binding in an OpenMP region.
template <typename Real>
struct Compliance {
  Real alpha_tilde, gamma;
  static Compliance of(double stiffness, double damping, Real h) {
    return {Real(1.0 / (stiffness * h * h)), Real(damping / (stiffness * h))};
  }
};

}  // namespace drape::xpbd
