// `symplectic`: the seed's semi-implicit Euler, v ← v + h·f/m, x ← x + h·v, with as many
// substeps per frame as the stability bound asks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "drape/error.h"
#include "forces.h"
#include "forces/bending.h"
#include "forces/bending_matrix.h"
#include "parallel.h"
#include "solver.h"

namespace drape {

double explicit_step_bound(const ClothModel& model, const std::vector<double>& inv_mass) {
  const int32_t n = model.size();
  const std::vector<double> k_sum = spring_sums(model, &Spring::stiffness),
                            c_sum = spring_sums(model, &Spring::damping);
  // Bending elements' rows: their Hessian's Gershgorin sums (none in the seed's model).
  std::vector<double> k_bend(n, 0.0), c_bend(n, 0.0);
  forces::bending_row_sums(model, k_bend, c_bend);
  double omega2 = 0.0, gamma = 0.0;
  for (int32_t i = 0; i < n; ++i) {
    omega2 = std::max(omega2, (2.0 * k_sum[i] + k_bend[i]) * inv_mass[i]);
    gamma = std::max(gamma, (2.0 * c_sum[i] + c_bend[i]) * inv_mass[i]);
  }
  if (omega2 == 0.0) return gamma == 0.0 ? std::numeric_limits<double>::infinity() : 2.0 / gamma;
  // Positive root of h²ω² + 2hγ − 4 = 0, written to avoid cancellation when γ² ≫ ω².
  return 4.0 / (gamma + std::sqrt(gamma * gamma + 4.0 * omega2));
}

namespace {

class Symplectic final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    force_.assign(w.model.size(), Vec3::Zero());
    frame_dt_ = def.dt;
    bending_.prepare(w.model);
    if (def.substeps > 0) {
      substeps_ = def.substeps;
      return;
    }
    const double h = def.safety * explicit_step_bound(w.model, w.state.inv_mass);
    const double needed = std::ceil(def.dt / h);
    if (!(needed <= def.max_substeps)) {
      throw InputError("solver.substeps",
                       "the symplectic method needs " + count_text(needed) +
                           " substeps per frame to stay stable, more than solver.max_substeps = " +
                           std::to_string(def.max_substeps) +
                           "; lower the stiffness or damping, raise the mass, use a smaller dt, "
                           "or fix solver.substeps yourself");
    }
    substeps_ = std::max(1, static_cast<int>(needed));
  }

  void step_frame(World& w, double dt) override {
    const int steps = substeps_in(dt, frame_dt_, substeps_);
    const double h = dt / steps;
    ClothState& s = w.state;
    const int32_t n = w.model.size();
    const bool wind = w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0;
    for (int k = 0; k < steps; ++k) {
      if (k > 0 && w.stop_here()) break;
      w.pose_colliders(w.time + k * h, w.time + (k + 1) * h);
      // 1. Forces at the start of the substep.
      const bool bending = !bending_.empty();
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) {
        force_[i] = w.model.mass[i] * w.forces.gravity;
        if (bending) force_[i] -= bending_.force_row(i, s.x, s.v);
      }
      forces::add_springs(w.model, s.x, s.v, force_);
      if (wind) {
        update_normals(w.model, s);
        forces::add_wind(w.model, s, w.forces.wind, w.time + k * h, force_);
      }
      // 2. Kick. Pinned and held particles have 1/m = 0 and stay exactly put.
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) s.v[i] += (h * s.inv_mass[i]) * force_[i];
      // 3. Drag, drift, long-range attachments, contacts.
      apply_air_drag(w, h);
      drift_constrain(w, h);
    }
    update_normals(w.model, s);
  }

  int substeps() const override { return substeps_; }
  bool stretch_is_energy() const override { return true; }
  int64_t workspace_bytes() const override {
    return heap_bytes(force_) + bending_.bytes();
  }

 private:
  int substeps_ = 1;
  double frame_dt_ = 0.0;
  std::vector<Vec3> force_;
  forces::BendingMatrix bending_;  // the elements' constant K and D
};

}  // namespace

std::unique_ptr<Solver> make_symplectic() { return std::make_unique<Symplectic>(); }

}  // namespace drape
