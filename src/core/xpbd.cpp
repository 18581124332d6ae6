// `xpbd`: extended position-based dynamics with small steps (Macklin, Müller & Chentanez 2016,
// "XPBD"; Macklin et al. 2019, "Small steps in physics simulation"): per substep, predict
// with the external forces, project every spring as a compliant distance constraint
// (α = 1/k, damping from the spring's c) by Gauss–Seidel colour by colour, apply long-range
// attachments, derive v = (x − x_prev)/h, resolve contacts.
//
// With one iteration per substep a spring reaches an effective stiffness of about
// min(k, m/h²), so the automatic substep count is the smallest with m/h² ≥ k for every spring.
#include <algorithm>
#include <cmath>
#include <string>

#include "constraints.h"
#include "drape/error.h"
#include "forces.h"
#include "long_range.h"
#include "parallel.h"
#include "solver.h"

namespace drape {

namespace {

constexpr int kDefaultIterations = 1;

class Xpbd final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    const int32_t n = w.model.size();
    x_prev_.assign(n, Vec3::Zero());
    accel_.assign(n, Vec3::Zero());
    lambda_.assign(w.model.springs.size(), 0.0);
    attachments_.prepare(w.model, w.state, w.long_range);
    iterations_ = def.iterations > 0 ? def.iterations : kDefaultIterations;
    if (def.substeps > 0) {
      substeps_ = def.substeps;
      return;
    }
    // m/h² ≥ k for the stiffest spring relative to its lighter free end: h ≤ 1/sqrt(k·w).
    double kw = 0.0;
    for (const Spring& s : w.model.springs)
      kw = std::max(kw, s.stiffness * std::max(w.state.inv_mass[s.i], w.state.inv_mass[s.j]));
    const double needed = std::ceil(def.dt * std::sqrt(kw));
    if (!(needed <= def.max_substeps)) {
      throw InputError("solver.substeps",
                       "the xpbd method needs " + std::to_string(needed) +
                           " substeps per frame to reach the springs' stiffness, more than "
                           "solver.max_substeps = " +
                           std::to_string(def.max_substeps) +
                           "; lower the stiffness, raise the mass, use a smaller dt, or fix "
                           "solver.substeps yourself (softer cloth)");
    }
    substeps_ = std::max(1, static_cast<int>(needed));
  }

  void step_frame(World& w, double dt) override {
    const double h = dt / substeps_;
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    // External acceleration, held over the frame: gravity plus the wind at the frame's start.
    // The wind does not depend on the substep's positions, so it is as stable at the frame
    // step as gravity, and evaluating it once keeps hundreds of substeps cheap.
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) accel_[i] = Vec3::Zero();
    if (w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0) {
      update_normals(m, s);
      forces::add_wind(m, s, w.forces.wind, w.time, accel_);
    }
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) accel_[i] = w.forces.gravity + s.inv_mass[i] * accel_[i];

    for (int k = 0; k < substeps_; ++k) {
      predict(s, n, h, w.forces.air_drag);
      for (int it = 0; it < iterations_; ++it) project_springs(m, s, h, it == 0);
      attachments_.apply(m, s, false);  // v follows from x below, so no velocity fix-up
      update_velocities(s, n, h);
      resolve_contacts(w.colliders, s);
    }
    update_normals(m, s);
  }

  int substeps() const override {
    return substeps_;
  }

 private:
  // 1. Predict: v += h·a, semi-implicit drag, x += h·v. Pinned and held particles stay put.
  void predict(ClothState& s, int32_t n, double h, double air_drag) {
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i)
      if (s.inv_mass[i] > 0.0) s.v[i] += h * accel_[i];
    forces::apply_drag(air_drag, s.inv_mass, h, s.v);
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      x_prev_[i] = s.x[i];
      if (s.inv_mass[i] > 0.0) s.x[i] += h * s.v[i];
    }
  }

  // 2. One Gauss–Seidel sweep over the springs, colour by colour (a colour's springs share no
  // particle, so they run in parallel with the same result as in order).
  void project_springs(const ClothModel& m, ClothState& s, double h, bool first) {
    for (int c = 0; c < m.colours(); ++c) {
      const int32_t begin = m.colour_begin[c], end = m.colour_begin[c + 1];
#pragma omp parallel for schedule(static) if (worth_threads(end - begin))
      for (int32_t k = begin; k < end; ++k) {
        const Spring& sp = m.springs[k];
        if (first) lambda_[k] = 0.0;
        if (sp.stiffness <= 0.0) continue;  // infinite compliance: no constraint
        const double alpha_tilde = 1.0 / (sp.stiffness * h * h);
        // β = c (N·s/m): γ = α̃·β·h²/h = c/(k·h) (Macklin et al. 2016, eq. 26).
        const double gamma = sp.damping / (sp.stiffness * h);
        const DistanceCorrection d = xpbd_distance(
            s.x[sp.i], s.inv_mass[sp.i], s.x[sp.j], s.inv_mass[sp.j], sp.rest, alpha_tilde, gamma,
            s.x[sp.i] - x_prev_[sp.i], s.x[sp.j] - x_prev_[sp.j], lambda_[k]);
        s.x[sp.i] += d.dxi;
        s.x[sp.j] += d.dxj;
        lambda_[k] += d.dlambda;
      }
    }
  }

  // 3. v = (x − x_prev)/h.
  void update_velocities(ClothState& s, int32_t n, double h) {
    const double inv_h = 1.0 / h;
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) s.v[i] = (s.x[i] - x_prev_[i]) * inv_h;
  }

  int substeps_ = 1;
  int iterations_ = kDefaultIterations;
  std::vector<Vec3> x_prev_;
  std::vector<Vec3> accel_;
  std::vector<double> lambda_;
  LongRange attachments_;
};

}  // namespace

std::unique_ptr<Solver> make_xpbd() {
  return std::make_unique<Xpbd>();
}

}  // namespace drape
