// `implicit`: backward Euler with one Newton step per substep (Baraff & Witkin 1998, "Large
// steps in cloth simulation"):
//   (M − h·∂f/∂v − h²·∂f/∂x) Δv = h·(f₀ + h·∂f/∂x·v₀),
// solved matrix-free by conjugate gradients with a 3×3 block-Jacobi preconditioner. Pinned and
// held particles (1/m = 0) are constrained to Δv = 0 by filtering (B&W §5.3): their
// preconditioner blocks are zero, so the search directions never move them — the constrained
// directions are removed from the system rather than penalised. A compressed spring's
// stiffness block drops its negative transverse term (forces::spring_stiffness with clamp) so
// the system matrix stays symmetric positive definite and CG applies.
//
// Contacts are constraints of the same solve (B&W §5.3–5.4): a particle that would move into a
// collider this substep has its normal velocity prescribed (to arrive at the surface, or to stay
// on it) and only its tangential directions are solved for, so its neighbours' springs see
// where it really goes. Projecting positions after a large step instead would stretch stiff
// springs by up to h²·g per step and pump energy into them. Friction then acts on the
// tangential velocity with the normal velocity change as the Coulomb bound. Long-range
// attachments at their limit are constrained the same way (without friction), up to two
// constraints per particle; the projection after the step catches the rest. A frame where a
// moving collider or a still ball moves fast relative to the cloth near it takes more substeps
// (ColliderSet::substeps_for): a small body is not swept round by large steps.
#include <algorithm>
#include <cmath>
#include <memory>

#include "fnv.h"
#include "forces.h"
#include "forces/bending_matrix.h"
#include "long_range.h"
#include "parallel.h"
#include "solver.h"
#include "system_factor.h"

namespace drape {

namespace {

// The preconditioner is chosen by cost, from the last solves' iteration counts (never from
// clocks, so a run's choices, and its bits, do not depend on the machine or the threads):
// block-Jacobi, cheap per iteration; a fresh factor of the system (SystemFactor), dear to make
// but then one iteration; or the last factor, lagged, as long as its iterations cost less than
// either. The costs, in ns on one core, were measured on denim over the sphere at 32² and 64²
// and on the lab's strip (they weigh the choices against each other; no time is promised).
constexpr double kJacobiNsPerParticle = 9.0;  // a block-Jacobi CG iteration: multiply, vectors
constexpr double kJacobiNsPerSpring = 4.0;
// A bending element, through the rows of forces::BendingMatrix: 3.1 ns fitted to the
// iterations timed on 32² and 64² denim (2026-12-06), 9 ns while the elements were looped over.
constexpr double kJacobiNsPerElement = 3.0;
constexpr double kSolveNsPerEntry = 2.2;     // a solve with the factor, per entry of L
constexpr double kFactoriseNsPerWork = 0.4;  // per unit of SystemFactor::factorise_work()
// Block-Jacobi solves that take fewer iterations than this never look at a factor (its pattern,
// ordering and counts cost memory and time once).
constexpr int kConsiderFactorAfter = 50;
// Whether a factor pays shows only over the substeps it is used: how fast it goes stale. So
// the factors' balance is kept (what block-Jacobi would have cost for their substeps, less
// what they cost), and while it is negative a fresh factor must pay this many times over. On
// the seed's stiff cloth landing on the sphere (`bench/scenes/drape.json` at 64², 1 s) a
// fresh factor just paid, the lagged one took 68 to 204 iterations after it, and without the
// balance the run took 8.4 s on one core against 5.3 s with block-Jacobi alone.
constexpr double kFactorMargin = 2.0;
// The balance starts this many factorisations above zero (one factor that did not pay, among
// many that did, leaves the margin at 1: the lab's 80-cell denim strip ran 15% slower when its
// second factor, which did not pay, doubled the margin) and is kept at most this many above, so
// that a cloth that changes from slow to fast is recognised after a factor or two.
constexpr double kFactorCreditStart = 2.0;
constexpr double kMaxFactorCredit = 4.0;

class Implicit final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    const int32_t n = w.model.size();
    for (auto* v : {&rhs_, &force_, &dv_, &r_, &s_, &c_, &q_, &contact_n_, &contact_surface_})
      v->assign(n, Vec3::Zero());
    contact_dvn_.assign(n, 0.0);
    contact_mu_.assign(n, 0.0);
    block_.assign(w.model.springs.size(), Mat3::Zero());
    diag_.assign(n, Mat3::Zero());
    precond_.assign(n, Mat3::Zero());
    filter_.assign(n, Mat3::Identity());
    // A factor stays while the springs and elements are the same (a grab or a new pin prepares
    // again): lagged, it is still a sound preconditioner, and the choice below replaces it
    // when it no longer pays.
    const uint64_t pattern = pattern_key(w.model);
    if (pattern != pattern_key_) {
      factor_.reset();
      factor_costs_ = false;
      next_ = Preconditioner::jacobi;
      jacobi_iterations_ = -1;
      pattern_key_ = pattern;
    }
    // The last solution stays a candidate first guess through a new preparation (changed pins,
    // masses or dt): any guess converges, and a scene prepared again unchanged goes on to the bit.
    if (last_dv_.size() != static_cast<size_t>(n)) {
      last_dv_.assign(n, Vec3::Zero());
      warm_ = false;
    }
    substeps_ = def.substeps > 0 ? def.substeps : 1;
    frame_dt_ = def.dt;
    tolerance_ = def.cg_tolerance;
    max_iterations_ = def.cg_max_iterations;
    bending_.prepare(w.model);
    list_incident(w.model);
  }

  void step_frame(World& w, double dt) override {
    ClothState& s = w.state;
    int steps = substeps_in(dt, frame_dt_, substeps_);
    if (w.bodies)  // a small body: substeps from its move relative to the cloth near it
      steps = std::max(steps, w.bodies->substeps_for(s.x, s.v, s.inv_mass, w.time, w.time + dt));
    if (w.features) steps = std::max(steps, kImplicitStepsAtSharpFeatures);
    const double h = dt / steps;
    const int32_t n = w.model.size();
    for (int k = 0; k < steps; ++k) {
      if (k > 0 && w.stop_here()) break;
      w.pose_colliders(w.time + k * h, w.time + (k + 1) * h);
      assemble(w, h, w.time + k * h);
      if (next_ == Preconditioner::fresh_factor) {
        next_ = Preconditioner::factor;
        stale_ = 0.0;
        spent_ = factorise_;
        spent_substeps_ = 0;
        if (!factor_->factorise(w.model, diag_, block_, h_, filter_)) {  // never expected
          next_ = Preconditioner::jacobi;
          factorise_ = HUGE_VAL;
        }
      }
      choose_next(w.model, solve(w.model, s));
      last_dv_ = dv_;
      warm_ = true;
      // Newton update with contact friction, then drag and the drift. (Drag after the solve
      // damps the one-step solve's outliers; taken before it the seed's sphere never came to
      // rest: README, Known traps.)
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) {
        s.v[i] += dv_[i];
        if (contact_dvn_[i] > 0.0) {  // on the velocity relative to the surface's
          Vec3 rel = s.v[i] - contact_surface_[i];
          apply_friction(contact_n_[i], contact_dvn_[i], contact_mu_[i], rel);
          s.v[i] = contact_surface_[i] + rel;
        }
      }
      apply_air_drag(w, h);
      drift_constrain(w, h);
    }
    update_normals(w.model, s);
  }

  int substeps() const override {
    return substeps_;
  }
  // Its drag is taken after the solve (README, Known traps).
  bool may_tear() const override {
    return true;
  }
  int64_t workspace_bytes() const override {
    return heap_bytes(rhs_, force_, dv_, r_, s_, c_, q_, last_dv_, contact_n_, contact_surface_,
                      contact_dvn_, contact_mu_, block_, diag_, precond_, filter_) +
           heap_bytes(incident_begin_, incident_) + bending_.bytes() +
           (factor_ ? factor_->bytes() : 0);
  }

 private:
  // 1. The right-hand side b = h·f₀ − h²·K·v₀ (K = −∂f/∂x, clamped), each spring's system
  // block D = h²K + h·c·d̂d̂ᵀ (c·d̂d̂ᵀ = −∂f/∂v), and the block-Jacobi preconditioner.
  void assemble(World& w, double h, double t) {
    h_ = h;
    h2_ = h * h;
    const ClothModel& m = w.model;
    ClothState& s = w.state;
    const int32_t n = m.size();
    const bool wind = w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0;
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      force_[i] = m.mass[i] * w.forces.gravity;
      diag_[i] = m.mass[i] * Mat3::Identity();
    }
    if (wind) {
      update_normals(m, s);
      forces::add_wind(m, s, w.forces.wind, t, force_);
    }
    // The external impulse h·f_ext starts the right-hand side; its M⁻¹-norm is the floor of
    // the CG stopping test.
    ext_norm2_ = deterministic_sum(n, [&](int64_t i) {
      rhs_[i] = h * force_[i];
      dv_[i] = s.inv_mass[i] * rhs_[i];  // the first guess, before contacts filter it
      return s.inv_mass[i] * rhs_[i].squaredNorm();
    });
    const double h2 = h * h;
    for (int c = 0; c < m.colours(); ++c) {
      const int32_t begin = m.colour_begin[c], end = m.colour_begin[c + 1];
#pragma omp parallel for schedule(static) if (colour_in_parallel(m, c))
      for (int32_t k = begin; k < end; ++k) {
        const Spring& sp = m.springs[k];
        const Vec3 &xi = s.x[sp.i], &xj = s.x[sp.j];
        const double ks = forces::acting_stiffness(xi, xj, sp.stiffness, sp.rest,
                                                   forces::compression_of(m, sp.kind));
        const Mat3 K = forces::spring_stiffness(xi, xj, ks, sp.rest, true);
        block_[k] = forces::implicit_spring_block(xi, xj, ks, sp.rest, sp.damping, h);
        const Vec3 fi = forces::spring_elastic(xi, xj, ks, sp.rest) +
                        forces::spring_damping(xi, xj, s.v[sp.i], s.v[sp.j], sp.damping);
        const Vec3 bi = h * fi - h2 * (K * (s.v[sp.i] - s.v[sp.j]));
        rhs_[sp.i] += bi;
        rhs_[sp.j] -= bi;
        force_[sp.i] += fi;
        force_[sp.j] -= fi;
        diag_[sp.i] += block_[k];
        diag_[sp.j] += block_[k];
      }
    }
    // Bending elements: their Hessian K = Σ k·w·wᵀ ⊗ I is constant and their damping
    // D = Σ d·w·wᵀ ⊗ I too, so they add h²K + h·D to the system and h·f₀ − h²·K·v₀ to the
    // right-hand side, f₀ = −(K·x + D·v).
    if (!bending_.empty()) {
      bending_.combine(h2, h);
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) {
        Vec3 kx = Vec3::Zero(), kv = Vec3::Zero(), dv = Vec3::Zero();
        bending_.for_row(i, [&](int32_t j, double k, double d) {
          kx += k * s.x[j];
          kv += k * s.v[j];
          dv += d * s.v[j];
        });
        const Vec3 f = -(kx + dv);
        rhs_[i] += h * f - h2 * kv;
        force_[i] += f;
        diag_[i].diagonal().array() += bending_.combined_diagonal(i);
      }
    }
    // Contacts, the filter S (I, I − nnᵀ or 0), the preconditioner S·P⁻¹·S (zero in the
    // constrained directions, so CG never moves along them) and the two first guesses
    // Δv = z + S·g, z the prescribed normal velocity change, g = h·f_ext/m (exact in free fall)
    // or the last substep's Δv (near zero at rest on a body, where the other would leave CG
    // the whole weight to undo); solve() starts from the better.
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      contact_dvn_[i] = 0.0;
      contact_mu_[i] = 0.0;
      filter_[i].setIdentity();
      if (s.inv_mass[i] == 0.0) {
        filter_[i].setZero();
        precond_[i].setZero();
        dv_[i].setZero();
        last_dv_[i].setZero();
        continue;
      }
      precond_[i] = diag_[i].inverse();
      const Vec3 predicted = s.v[i] + dv_[i];  // with the external forces only
      // Up to two constraints the particle would violate this substep: colliders (normal
      // outward, gap to the thickness), then long-range limits (normal toward the pin, gap
      // to the limit). A particle below two pins is usually at both limits at once.
      Vec3 nrm[2];
      double target[2] = {0.0, 0.0};
      int count = 0;
      // `t_n`: the least normal velocity that keeps the particle outside by the substep's end;
      // `surface`: the velocity of what the particle touches (a moving collider's, else 0).
      auto consider = [&](const Vec3& n_out, double t_n, double mu, const Vec3& surface) {
        if (count == 2 || predicted.dot(n_out) >= t_n) return;
        if (count == 0 || contact_dvn_[i] == 0.0) {  // friction: the first collider's
          contact_n_[i] = n_out;
          contact_dvn_[i] = mu > 0.0 ? t_n - predicted.dot(n_out) : 0.0;
          contact_mu_[i] = mu;
          contact_surface_[i] = surface;
        }
        nrm[count] = n_out;
        target[count] = t_n;
        ++count;
      };
      for (const Collider& col : w.colliders) {
        // A still surface beyond this substep's travel cannot be met.
        if (!col.moving && clear_of(col, s.x[i], h * predicted.norm())) continue;
        Vec3 n_out;
        const double gap = signed_distance(col, s.x[i], n_out) - col.thickness;
        // A still surface: arrive at it, or stop where it is reached. A moving one is posed where
        // it is at the substep's end, so the gap already holds its motion: the particle must
        // cover it (leave it, when the surface has overtaken the particle) within the substep.
        // (Adding the surface's own normal velocity to that counted its motion twice, and shoved
        // cloth ahead of a fast ball aside before the ball reached it.)
        const double t_n = col.moving ? -gap / h : -std::max(gap, 0.0) / h;
        consider(n_out, t_n, col.friction, col.surface_velocity(s.x[i]));
      }
      const LongRange& tethers = w.attachments;
      for (int k = 0; k < tethers.tethers() && tethers.pin(i, k) >= 0; ++k) {
        const Vec3 d = s.x[tethers.pin(i, k)] - s.x[i];
        const double len = d.norm();
        if (len > 0.0)
          consider(d / len, -std::max(tethers.limit(i, k) - len, 0.0) / h, 0.0, Vec3::Zero());
      }
      if (count == 0) continue;
      // Filter S = I − e₁e₁ᵀ − e₂e₂ᵀ over an orthonormal basis of the constrained normals, and
      // the constrained part of Δv that meets both prescribed normal velocities
      // ((v + Δv)·n_k = target_k; the system is triangular in that basis).
      const Vec3 e1 = nrm[0];
      Vec3 e2 = Vec3::Zero();
      if (count == 2) {
        const Vec3 r2 = nrm[1] - nrm[1].dot(e1) * e1;
        if (r2.norm() > 1e-6) e2 = r2.normalized();
      }
      const Mat3 S = Mat3::Identity() - e1 * e1.transpose() - e2 * e2.transpose();
      const double a1 = target[0] - s.v[i].dot(nrm[0]);
      const double a2 =
          e2.squaredNorm() > 0.0
              ? (target[1] - s.v[i].dot(nrm[1]) - a1 * e1.dot(nrm[1])) / e2.dot(nrm[1])
              : 0.0;
      filter_[i] = S;
      precond_[i] = S * precond_[i] * S;
      dv_[i] = S * dv_[i] + a1 * e1 + a2 * e2;
      last_dv_[i] = S * last_dv_[i] + a1 * e1 + a2 * e2;
    }
  }

  // q = A·p: on particle i, m_i·p_i + Σ over its springs s to j of D_s·(p_i − p_j) + the
  // bending elements' (h²K + h·D)·p. Each particle gathers its own row, so one loop shares the
  // particles out to threads (scattering each spring's product to its two ends instead took a
  // parallel loop per colour of springs: 377 → 335 ms/frame on denim at 128² when replaced).
  void multiply(const ClothModel& m, const std::vector<Vec3>& p, std::vector<Vec3>& q) const {
    const int32_t n = m.size();
    const bool bending = !bending_.empty();
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      Vec3 sum = m.mass[i] * p[i];
      for (int32_t k = incident_begin_[i]; k < incident_begin_[i + 1]; ++k) {
        const Incident& e = incident_[k];
        sum += block_[e.spring] * (p[i] - p[e.other]);
      }
      if (bending) sum += bending_.combined_row(i, p);
      q[i] = sum;
    }
  }

  // Each particle's springs, for multiply(): by particle, in the springs' order.
  void list_incident(const ClothModel& m) {
    const int32_t n = m.size();
    incident_begin_.assign(n + 1, 0);
    for (const Spring& sp : m.springs) ++incident_begin_[sp.i + 1], ++incident_begin_[sp.j + 1];
    for (int32_t i = 0; i < n; ++i) incident_begin_[i + 1] += incident_begin_[i];
    incident_.resize(incident_begin_[n]);
    std::vector<int32_t> fill(incident_begin_.begin(), incident_begin_.end() - 1);
    for (int32_t k = 0; k < static_cast<int32_t>(m.springs.size()); ++k) {
      const Spring& sp = m.springs[k];
      incident_[fill[sp.i]++] = {k, sp.j};
      incident_[fill[sp.j]++] = {k, sp.i};
    }
  }

  // Runs update(i) on every particle (it sets r_[i]), then z = P·r_ with the preconditioner in
  // use; returns r_ᵀz. Block-Jacobi does it in one pass, the factor needs all of r_ first.
  template <class Update>
  double update_and_precondition(int32_t n, Update update, std::vector<Vec3>& z) {
    if (next_ != Preconditioner::factor)
      return deterministic_sum(n, [&](int64_t i) {
        update(i);
        z[i] = precond_[i] * r_[i];
        return r_[i].dot(z[i]);
      });
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) update(i);
    factor_->apply(r_, filter_, z);
    return deterministic_sum(n, [&](int64_t i) { return r_[i].dot(z[i]); });
  }

  // The residual r = b − A·x (zero on pinned particles).
  void residual(const ClothModel& m, const ClothState& s, const std::vector<Vec3>& x) {
    multiply(m, x, q_);
    const int32_t n = m.size();
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i)
      r_[i] = s.inv_mass[i] > 0.0 ? Vec3(rhs_[i] - q_[i]) : Vec3::Zero();
  }

  // After a solve of `iterations` with next_'s preconditioner: the one for the next substep.
  void choose_next(const ClothModel& m, int iterations) {
    const double jacobi = kJacobiNsPerParticle * m.size() +
                          kJacobiNsPerSpring * static_cast<double>(m.springs.size()) +
                          kJacobiNsPerElement * static_cast<double>(m.bending.size());
    const double fresh = factorise_ + 2 * with_factor_;  // a fresh factor takes one iteration
    if (next_ == Preconditioner::jacobi) {
      jacobi_iterations_ = iterations;
      if (iterations < kConsiderFactorAfter ||
          (!factor_costs_ && m.size() > SystemFactor::kMaxParticles))
        return;
      if (!factor_costs_) {  // the factor's costs: its pattern analysed, once
        factor_ = std::make_unique<SystemFactor>();
        factor_->prepare(m);
        with_factor_ = jacobi + kSolveNsPerEntry * static_cast<double>(factor_->entries());
        factorise_ = kFactoriseNsPerWork * factor_->factorise_work();
        credit_ = kFactorCreditStart * factorise_;
        factor_costs_ = true;
        return choose_next(m, iterations);
      }
      // A fresh factor must pay on this one substep, by the margin learnt: where the cloth
      // moves fast (landing, folding, contacts coming and going) it is stale by the next, worse
      // than block-Jacobi.
      if ((iterations + 1) * jacobi > margin() * fresh) {
        next_ = Preconditioner::fresh_factor;
        if (!factor_) {
          factor_ = std::make_unique<SystemFactor>();
          factor_->prepare(m);
        }
      } else if (!factor_ready()) {
        factor_.reset();  // the analysis only: its memory back
      }
      return;
    }
    // With a factor: its iterations beyond a fresh factor's one add up, and once they have
    // cost a factorisation the next substep takes a fresh one (so the factorisations cost at
    // most what their lagging saved), unless block-Jacobi, as last seen, is cheaper still.
    stale_ += (iterations - 1) * with_factor_;
    spent_ += (iterations + 1) * with_factor_;
    ++spent_substeps_;
    const double lagged = stale_ < factorise_ ? (iterations + 1) * with_factor_ : HUGE_VAL;
    const double block_jacobi =
        jacobi_iterations_ >= 0 ? (jacobi_iterations_ + 1) * jacobi : HUGE_VAL;
    if (lagged <= std::min(block_jacobi, fresh)) {
      next_ = Preconditioner::factor;
      return;
    }
    // This factor is given up: its balance against block-Jacobi as last seen.
    if (block_jacobi < HUGE_VAL)
      credit_ = std::min(credit_ + spent_substeps_ * block_jacobi - spent_,
                         kMaxFactorCredit * factorise_);
    next_ = block_jacobi < margin() * fresh ? Preconditioner::jacobi : Preconditioner::fresh_factor;
  }

  double margin() const {
    return credit_ < 0.0 ? kFactorMargin : 1.0;
  }

  bool factor_ready() const {
    return factor_ && factor_->ready();
  }

  // φ(x) = ½xᵀAx − bᵀx = −½xᵀ(b + r) with r the residual residual() left for x. Of two
  // guesses in the same affine space (the same prescribed normal parts) the one with the lower
  // φ is the nearer to the solution in A's norm, the norm CG reduces.
  double objective(const ClothModel& m, const std::vector<Vec3>& x) const {
    return deterministic_sum(m.size(), [&](int64_t i) { return -0.5 * x[i].dot(rhs_[i] + r_[i]); });
  }

  // 2. Filtered preconditioned CG from the first guess with the lower φ (hundreds fewer
  // iterations under load at rest, where the last Δv wins, and none lost in free fall, where
  // h·f_ext/m does). Weighing them costs one product, two where the last Δv wins: there CG
  // takes hundreds. Stops when the residual's preconditioned norm falls below tolerance × the
  // larger of its start and the external impulse, so it neither chases round-off nor stops
  // early at rest.
  int solve(const ClothModel& m, const ClothState& s) {
    const int32_t n = m.size();
    double last = 0.0;  // φ of the last Δv
    if (warm_) {
      residual(m, s, last_dv_);
      last = objective(m, last_dv_);
    }
    residual(m, s, dv_);
    if (warm_ && last < objective(m, dv_)) {
      dv_.swap(last_dv_);
      residual(m, s, dv_);
    }
    double delta = update_and_precondition(
        n, [](int64_t) {}, c_);
    const double threshold = tolerance_ * tolerance_ * std::max(delta, ext_norm2_);
    int it = 0;
    for (; it < max_iterations_ && delta > threshold; ++it) {
      multiply(m, c_, q_);
      const double cq = deterministic_sum(n, [&](int64_t i) { return c_[i].dot(q_[i]); });
      if (!(cq > 0.0)) break;  // only round-off left (A is positive definite on free particles)
      const double alpha = delta / cq;
      const double next = update_and_precondition(
          n,
          [&](int64_t i) {
            dv_[i] += alpha * c_[i];
            r_[i] -= alpha * q_[i];
          },
          s_);
      const double beta = next / delta;
      delta = next;
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) c_[i] = s_[i] + beta * c_[i];
    }
    return it;
  }

  // Identifies the factor's pattern: the particles, the springs' ends, the elements' corners.
  static uint64_t pattern_key(const ClothModel& m) {
    Fnv1a hash;
    hash.mix(static_cast<uint64_t>(m.size()));
    for (const Spring& sp : m.springs)
      hash.mix((uint64_t(uint32_t(sp.i)) << 32) | uint32_t(sp.j));
    for (const BendingElement& b : m.bending)
      for (int32_t v : b.v) hash.mix(uint32_t(v));
    return hash.key;
  }

  int substeps_ = 1;
  double frame_dt_ = 0.0;
  double h_ = 0.0, h2_ = 0.0;  // the substep's h and h² (the bending blocks are formed from them)
  double tolerance_ = 1e-5;
  int max_iterations_ = 2000;
  bool warm_ = false;  // last_dv_ holds a solution for this model
  double ext_norm2_ = 0.0;
  std::vector<Vec3> rhs_, force_, dv_, r_, s_, c_, q_, last_dv_;
  std::vector<Vec3> contact_n_;        // outward normal of the particle's contact
  std::vector<Vec3> contact_surface_;  // the velocity of the surface it touches (m/s)
  std::vector<double> contact_dvn_;    // its normal velocity change (m/s), 0 = no contact
  std::vector<double> contact_mu_;     // its friction coefficient
  std::vector<Mat3> block_;            // per spring: h²K + h·C
  std::vector<Mat3> diag_;             // per particle: the system matrix's diagonal block
  std::vector<Mat3> precond_;          // its inverse, zero on constrained particles
  std::vector<Mat3> filter_;           // per particle: S (I, a projection, 0 when pinned)
  forces::BendingMatrix bending_;      // the elements' constant K and D
  struct Incident {
    int32_t spring, other;  // a spring of the particle, and its other end
  };
  std::vector<int32_t> incident_begin_;  // per particle, its first in incident_
  std::vector<Incident> incident_;
  // The preconditioner of the next solve: block-Jacobi, factor_ as it is, or factor_ made anew
  // for it (then `factor`).
  enum class Preconditioner { jacobi, factor, fresh_factor };
  Preconditioner next_ = Preconditioner::jacobi;
  std::unique_ptr<SystemFactor> factor_;  // made when block-Jacobi is slow
  uint64_t pattern_key_ = 0;              // the model factor_ and its costs are for
  bool factor_costs_ = false;             // with_factor_ and factorise_ are known
  double with_factor_ = 0.0;              // ns: an iteration preconditioned by the factor
  double factorise_ = 0.0;                // ns: a factorisation
  double stale_ = 0.0;          // ns: the iterations the factor in use took beyond one, summed
  int jacobi_iterations_ = -1;  // the last block-Jacobi solve's, −1 before any
  double spent_ = 0.0;          // ns: the factor in use, its factorisation and solves so far
  int spent_substeps_ = 0;      // the substeps it solved
  double credit_ = 0.0;         // ns: what the factors given up saved against block-Jacobi
};

}  // namespace

std::unique_ptr<Solver> make_implicit() {
  return std::make_unique<Implicit>();
}

}  // namespace drape
