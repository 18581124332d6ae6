// `fast`: implicit Euler for mass–springs by local/global iterations (Liu, Bargteil, O'Brien &
// Kavan 2013, "Fast simulation of mass-spring systems"), Chebyshev-accelerated (Wang 2015,
// "A Chebyshev semi-iterative approach for accelerating projective and position-based
// dynamics"). Each substep minimises
//   ½(x − y)ᵀM(x − y) + (h/2)(x − x₀)ᵀC(x − x₀) + h²·Σ_s ½k_s|x_j − x_i − d_s|²
// over x and the spring directions d_s (|d_s| = L_s), with y = x₀ + h·v₀ + h²·M⁻¹f_ext:
//   local:  d_s = L_s·(x_j − x_i)/|x_j − x_i|;
//   global: (M + hC + h²L)·x = M·y + hC·x₀ + h²·J·d, the matrix fixed and prefactored.
// Damping: per-spring damping along the current spring direction would change the matrix every
// step, and explicit damping blows up at h = 1/60 s. Each spring's c is in the prefactored
// matrix on the full relative move of its ends (C = Σ_s c_s·A_sA_sᵀ, a weighted graph
// Laplacian), implicitly: unconditionally stable, momentum-conserving. For the seed's springs
// it acts so, across the spring too (bending and swinging fold motion), more than the other
// methods damp. A material's damping is Rayleigh's, β·K, and K at rest has nothing across a
// spring: there the local step gives the damping term a target, the start's e₀ moved by the
// iterate's relative move across the spring, as it gives the spring its direction, so that at
// convergence only the move along the spring is damped. (Across, the material's stretch
// springs, β·k with k in the thousands of N/m, held a Cusick disc of denim nearly flat for
// 10 s.)
// Contacts: the inertial target y is projected out of the colliders before the iterations, and
// a stiff term w·½|x − p|² (p: the iterate moved out of the colliders and inside the long-range
// attachments' limits) holds a particle that touches or approaches a collider or a limit at the
// surface inside the solve, so the solve relaxes the springs around where the contact puts it;
// projecting only after the solve would stretch stiff springs by up to h²·g each step and pump
// energy into them. The term lives in the factorised matrix, and only particles that need it
// carry it: on every other particle it would brake all motion (falling included) to a crawl,
// since w ≫ m. When that set changes the matrix is refactorised numerically (its pattern is
// fixed). Coulomb friction acts inside the solve, through where the term pulls (grip()), its
// bound the normal push of y's projection; what the springs still push inside is resolved
// after the solve as in the other methods.
// Pinned and held particles are eliminated (their positions move to the right-hand side), so the
// factorisation depends on them: prepare() refactorises, and the Simulation calls it whenever
// pins, the held particle, masses, stiffness or dt change.
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <vector>

#include "bounded_count.h"
#include "drape/error.h"
#include "forces.h"
#include "forces/bending.h"
#include "long_range.h"
#include "parallel.h"
#include "solver.h"
#include "sparse_cholesky.h"

namespace drape {

namespace {

constexpr int kDefaultIterations = 10;
// Chebyshev starts after this many plain iterations (Wang 2015 §4 delays it: the first
// iterations' error does not yet decay at the asymptotic rate).
constexpr int kChebyshevDelay = 2;
// The contact term's weight in units of h²·(the stiffest spring): stiff enough that a contact
// holds against the springs pulling the cloth in, soft enough not to slow the iterations much.
constexpr double kContactWeight = 4.0;

class Fast final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    def_ = def;
    build(w, def.substeps > 0 ? def.substeps : 1);
  }

  bool steps_any_dt() const override { return false; }

  void step_frame(World& w, double dt) override {
    (void)dt;  // h_ was fixed in build(), with the factorisation (dt never changes between)
    choose_substeps(w);
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    const std::vector<int>& perm = cholesky_.permutation();  // unknown → row of the factor
    for (int k = 0; k < substeps_; ++k) {
      if (k > 0 && w.stop_here()) break;
      w.pose_colliders(w.time + k * h_, w.time + (k + 1) * h_);
      inertia(w, w.time + k * h_);
      const double h2 = h_ * h_;
      double omega = 1.0;
      for (int it = 0; it < iterations_; ++it) {
        local_and_rhs(m, w.colliders, w.attachments, h_, h2);
        global_solve();
        omega = chebyshev_weight(it, omega);
        // x_{k+1} = ω(x̂ − x_{k−1}) + x_{k−1} (Wang 2015, eq. 12 with γ = 1); ω = 1: x̂.
#pragma omp parallel for schedule(static) if (worth_threads(n))
        for (int32_t i = 0; i < n; ++i) {
          const int32_t f = free_[i];
          if (f < 0) continue;
          const int32_t row = perm[f];  // undo the permutation: x = Pᵀ·(P·x)
          const Vec3 xhat(X_(row, 0), X_(row, 1), X_(row, 2));
          const Vec3 next = omega * (xhat - xkm1_[i]) + xkm1_[i];
          xkm1_[i] = xk_[i];
          xk_[i] = next;
        }
      }
      // v = (x − x₀)/h: implicit Euler's velocity.
#pragma omp parallel for schedule(static) if (worth_threads(n))
      for (int32_t i = 0; i < n; ++i) {
        if (free_[i] < 0) continue;
        s.x[i] = xk_[i];
        s.v[i] = (xk_[i] - x0_[i]) / h_;
        if (contact_dvn_[i] > 0.0) {  // on the velocity relative to the surface's
          Vec3 rel = s.v[i] - contact_surface_[i];
          const double left = contact_dvn_[i] * (1.0 - contact_gripped_[i]);
          if (left > 0.0) apply_friction(contact_n_[i], left, contact_mu_[i], rel);
          s.v[i] = contact_surface_[i] + rel;
        }
      }
      w.attachments.apply(s, true);
      resolve_all_contacts(w);
    }
    update_normals(m, s);
  }

  int substeps() const override {
    return substeps_;
  }
  int64_t workspace_bytes() const override {
    // The factor L and the system matrix kept for refactorising (with its diagonal); the
    // factorisation keeps a few more integers per unknown (permutations, elimination tree).
    return cholesky_.bytes() + (diagonal_.size() + X_.size()) * int64_t{sizeof(double)} +
           heap_bytes(held_, held_now_, free_, diag_at_, x0_, y_, xk_, xkm1_, b0_, rhs_, force_,
                      contact_n_, contact_surface_, contact_dvn_, contact_mu_, contact_gripped_);
  }

 private:
  // Cloth coming fast at a small still ball parts round it in a step this long (a sheet dropped
  // onto a ball of radius 10 cm at 10 m/s went through at frame 61): the frames where that can
  // happen take the substeps ColliderSet::substeps_for asks for (still balls only: the curtain's
  // moving ball holds without), and frames at sharp features kFastStepsAtSharpFeatures; the system
  // built and factorised again for their h, and the scene's substeps after.
  void choose_substeps(const World& w) {
    int substeps = def_.substeps > 0 ? def_.substeps : 1;
    if (w.bodies)
      substeps = std::max(
          substeps, w.bodies->substeps_for(w.state.x, w.state.v, w.state.inv_mass, w.time,
                                           w.time + def_.dt, ColliderSet::Counted::still_round));
    if (w.features) substeps = std::max(substeps, kFastStepsAtSharpFeatures);
    if (substeps != substeps_) build(w, substeps);
  }

  // Everything prepare() makes, for `substeps` a frame of def_.dt.
  void build(const World& w, int substeps) {
    const SolverDef& def = def_;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    substeps_ = substeps;
    h_ = def.dt / substeps_;
    rho_ = def.chebyshev_rho > 0.0 ? def.chebyshev_rho : estimate_rho(w, h_);
    // Chebyshev's error falls by about 1 − sqrt(1 − ρ²) per iteration: enough iterations for
    // e^-2 of the slowest error, at least 10 (Liu et al.'s choice), at most 200.
    iterations_ = def.iterations > 0
                      ? def.iterations
                      : ceil_count(2.0 / std::sqrt(1.0 - rho_ * rho_), kDefaultIterations, 200);

    // Free particles are the unknowns.
    free_.assign(n, -1);
    int32_t free = 0;
    for (int32_t i = 0; i < n; ++i)
      if (w.state.inv_mass[i] > 0.0) free_[i] = free++;
    free_count_ = free;

    using Triplet = Eigen::Triplet<double>;
    std::vector<Triplet> t;
    t.reserve(static_cast<size_t>(free) + 4 * m.springs.size());
    for (int32_t i = 0; i < n; ++i)
      if (free_[i] >= 0) t.emplace_back(free_[i], free_[i], m.mass[i]);
    for (const Spring& s : m.springs) {
      const double a = h_ * s.damping + h_ * h_ * s.stiffness;
      const int32_t fi = free_[s.i], fj = free_[s.j];
      if (fi >= 0) t.emplace_back(fi, fi, a);
      if (fj >= 0) t.emplace_back(fj, fj, a);
      if (fi >= 0 && fj >= 0) {
        t.emplace_back(fi, fj, -a);
        t.emplace_back(fj, fi, -a);
      }
    }
    // Bending elements are quadratic (Bergou et al. 2006): their energy h²·½k|Σ w x|² and
    // damping (h/2)·d|Σ w (x − x₀)|² enter the prefactored matrix exactly, with no local step.
    for (const BendingElement& b : m.bending) {
      const double a = h_ * h_ * b.stiffness + h_ * b.damping;
      for (int p = 0; p < 4; ++p) {
        const int32_t fp = free_[b.v[p]];
        if (fp < 0) continue;
        for (int q = 0; q < 4; ++q) {
          const int32_t fq = free_[b.v[q]];
          if (fq >= 0) t.emplace_back(fp, fq, a * b.w[p] * b.w[q]);
        }
      }
    }
    // Contacts as a term of the minimised energy, w·½|x − p|² with p the particle's current
    // iterate moved out of the colliders (the local step finds p like a spring's direction): a
    // stiff pull to the surface where something touches. Projecting only the inertial target y
    // would not do: h²k ≫ m, so stiff springs overrule it. Long-range attachments join the same
    // term: p is also moved inside each pin's limit.
    double k_max = 0.0;
    for (const Spring& s : m.springs) k_max = std::max(k_max, s.stiffness);
    compressed_soft_ = m.compression != 1.0;
    damped_along_ = m.material;
    contact_weight_ =
        w.colliders.empty() && !w.attachments.active() ? 0.0 : kContactWeight * h_ * h_ * k_max;
    {
      Eigen::SparseMatrix<double> a(free, free);
      a.setFromTriplets(t.begin(), t.end());
      diagonal_ = a.diagonal();
      if (free > 0) cholesky_.analyse(a);
    }
    diag_at_.resize(free);
    for (int32_t f = 0; f < free; ++f) diag_at_[f] = cholesky_.find(f, f);
    held_.assign(n, 0);
    held_now_.assign(n, 0);
    if (free > 0) refactorise();

    for (auto* v : {&x0_, &y_, &xk_, &xkm1_, &b0_, &rhs_, &force_, &contact_n_, &contact_surface_})
      v->assign(n, Vec3::Zero());
    contact_dvn_.assign(n, 0.0);
    contact_gripped_.assign(n, 0.0);
    contact_mu_.assign(n, 0.0);
    X_.setZero(free, 3);
  }

  // 1. Drag (semi-implicit, on v₀), the inertial target y, and the constant part of the
  // right-hand side b₀ = M·y + hC·x₀ + (hc + h²k)·x_j for each spring to a fixed particle j.
  void inertia(World& w, double t) {
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    apply_air_drag(w, h_);
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) force_[i] = m.mass[i] * w.forces.gravity;
    if (w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0) {
      update_normals(m, s);
      forces::add_wind(m, s, w.forces.wind, t, force_);
    }
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      held_now_[i] = 0;
      x0_[i] = s.x[i];
      y_[i] = free_[i] >= 0 ? Vec3(s.x[i] + h_ * s.v[i] + (h_ * h_ * s.inv_mass[i]) * force_[i])
                            : s.x[i];
      // Contacts: the inertial target is moved out of the colliders, so the solve pulls the
      // cloth to the surface rather than into it.
      contact_dvn_[i] = 0.0;
      contact_gripped_[i] = 0.0;
      if (free_[i] >= 0) {
        // The contact term holds particles whose target lies inside a collider or beyond an
        // attachment's limit, or within this step's travel of either.
        const double reach = h_ * s.v[i].norm();
        held_now_[i] = w.attachments.within_reach(s.x, i, y_[i], reach);
        for (const Collider& col : w.colliders) {
          Vec3 nrm;
          if (!col.moving && clear_of(col, y_[i], reach)) continue;
          held_now_[i] |= signed_distance(col, y_[i], nrm) - col.thickness < reach;
          const double moved = project_out(col, s.x[i], y_[i], nrm);
          if (moved > 0.0) {
            contact_n_[i] = nrm;
            contact_dvn_[i] = moved / h_;
            contact_mu_[i] = col.friction;
            contact_surface_[i] = col.surface_velocity(y_[i]);
          }
        }
      }
      b0_[i] = m.mass[i] * y_[i];
      // The iterations start from x₀ + h·v₀, not from y: then a state at rest is a fixed point
      // of the step only where the forces balance, whatever the iteration count, so the
      // static shape is the true equilibrium (starting from y, the unconverged part of the
      // h²·g pull would leave a bias that sags further). Free fall stays exact: the first
      // global step reaches y. A particle whose target was pushed out of a collider starts
      // there instead: the contact term holds it to its iterate, tangentially too, and lets it
      // go only over many iterations (its weight is many times its mass), so started from
      // x₀ + h·v₀ its slide along the surface was what the iterations left of gravity's pull:
      // 4% of it without Chebyshev, 116% with (its weights, tuned to the springs, overshoot
      // these slow modes), and a patch on a box tilted 35° with μ = 0.5 slid faster than
      // Coulomb's g(sin θ − μ cos θ) allows. Friction moves that start back (grip()).
      xk_[i] = free_[i] >= 0 ? Vec3(s.x[i] + h_ * s.v[i]) : s.x[i];
      if (contact_dvn_[i] > 0.0) {
        xk_[i] = y_[i];
        pull_back(i, contact_mu_[i] * h_ * contact_dvn_[i], xk_[i]);
      }
      xkm1_[i] = xk_[i];
    }
    if (contact_weight_ > 0.0 && held_now_ != held_) refactorise();
    const double h = h_, h2 = h_ * h_;
    for (int c = 0; c < m.colours(); ++c) {
      const int32_t begin = m.colour_begin[c], end = m.colour_begin[c + 1];
#pragma omp parallel for schedule(static) if (colour_in_parallel(m, c))
      for (int32_t k = begin; k < end; ++k) {
        const Spring& sp = m.springs[k];
        const double a = h * sp.damping + h2 * sp.stiffness;
        if (!damped_along_) {  // else the local step gives the damping its target
          const Vec3 damp = (h * sp.damping) * (x0_[sp.i] - x0_[sp.j]);
          b0_[sp.i] += damp;
          b0_[sp.j] -= damp;
        }
        if (free_[sp.j] < 0) b0_[sp.i] += a * x0_[sp.j];
        if (free_[sp.i] < 0) b0_[sp.j] += a * x0_[sp.i];
      }
    }
    bending_rhs(m);
  }

  // Moves q back against its tangential move this step relative to the surface it touches,
  // q − x₀ − h·v_surface, by at most `limit` (m); returns how far.
  double pull_back(int32_t i, double limit, Vec3& q) const {
    const Vec3& nrm = contact_n_[i];
    const Vec3 move = q - x0_[i] - h_ * contact_surface_[i];
    const Vec3 tangential = move - move.dot(nrm) * nrm;
    const double len = tangential.norm();
    const double taken = std::min(len, limit);
    if (taken > 0.0) q -= (taken / len) * tangential;
    return taken;
  }

  // The bending elements' constant right-hand side: their damping's h·d·w_a·Σ w_b x₀_b, and
  // the coupling to fixed corners, −(h²k + h·d)·w_a·w_b·x_b, moved over from the matrix.
  void bending_rhs(const ClothModel& m) {
    for (const BendingElement& b : m.bending) {
      const double a = h_ * h_ * b.stiffness + h_ * b.damping;
      const Vec3 damp = (h_ * b.damping) * forces::bending_vector(b, x0_);
      Vec3 fixed = Vec3::Zero();
      for (int q = 0; q < 4; ++q)
        if (free_[b.v[q]] < 0) fixed += b.w[q] * x0_[b.v[q]];
      for (int p = 0; p < 4; ++p) b0_[b.v[p]] += b.w[p] * (damp - a * fixed);
    }
  }

  // Coulomb friction inside the solve, for a particle whose target y was pushed out of a
  // collider by a distance δ (m/h²·δ is the normal force). The contact term w·½|x − p|² pulls
  // with w·(p − x): p moved back against the particle's tangential move (relative to the
  // surface) by at most μ·δ·m/w makes that a friction force of at most μ times the normal one,
  // against the move that springs and gravity make together. The contact term lets a particle
  // slide only slowly over the iterations (w ≫ m), so the iterations start from y moved back by
  // at most μ·δ, where a lone particle ends. The part of the limit used in the last iteration
  // is kept: the velocity friction after the solve takes only what is left. (Friction on the
  // velocity alone came after the solve had slid the cloth h²·g·sin θ a step: a patch crept
  // 2.8 cm in 0.5 s down a 20° slope with μ = 0.5, where Coulomb's law holds it. On the
  // inertial target y itself it opposed gravity where the springs were lifting the cloth: a disc
  // resting on a ball slid off.)
  void grip(int32_t i, double mass, Vec3& p) {
    const double limit = contact_mu_[i] * h_ * contact_dvn_[i] * mass / contact_weight_;
    contact_gripped_[i] = limit > 0.0 ? pull_back(i, limit, p) / limit : 0.0;
  }

  // 2. Local step (the best spring directions for x_k) scattered into the right-hand side
  // b₀ + h²·J·d, then gathered into the permuted unknowns.
  void local_and_rhs(const ClothModel& m, const std::vector<Collider>& colliders,
                     const LongRange& attachments, double h, double h2) {
    const int32_t n = m.size();
    // Contact term w·|x − p|² on the particles that carry it (see prepare): p is x_k moved
    // inside the attachments' limits and out of the colliders.
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      rhs_[i] = b0_[i];
      if (!held_[i]) continue;
      Vec3 p = xk_[i], nrm;
      attachments.project(xk_, i, p);
      for (const Collider& col : colliders) project_out(col, p, nrm);
      if (contact_dvn_[i] > 0.0) grip(i, m.mass[i], p);
      rhs_[i] += contact_weight_ * p;
    }
    for (int c = 0; c < m.colours(); ++c) {
      const int32_t begin = m.colour_begin[c], end = m.colour_begin[c + 1];
#pragma omp parallel for schedule(static) if (colour_in_parallel(m, c))
      for (int32_t k = begin; k < end; ++k) {
        const Spring& sp = m.springs[k];
        const Vec3 e = xk_[sp.j] - xk_[sp.i];
        const double len = e.norm();
        if (len == 0.0) continue;  // any direction is as good; none adds nothing
        // A compressed spring of a material acts with compression·k (Choi & Ko 2002); with k
        // fixed in the matrix, the target length (1 − c)·|e| + c·L gives that force at x_k.
        double target = sp.rest;
        if (compressed_soft_ && len < sp.rest && sp.kind == SpringKind::structural)
          target = (1.0 - m.compression) * len + m.compression * sp.rest;
        const Vec3 d = (h2 * sp.stiffness * target / len) * e;
        rhs_[sp.i] -= d;
        rhs_[sp.j] += d;
        if (damped_along_) {
          // The damping term (h/2)·c·|e − t|² aims at the start's e₀ moved by the step's
          // relative move across the spring: it resists the move along it alone.
          const Vec3 start = x0_[sp.j] - x0_[sp.i], move = e - start;
          const Vec3 t = (h * sp.damping) * (start + move - (move.dot(e) / (len * len)) * e);
          rhs_[sp.i] -= t;
          rhs_[sp.j] += t;
        }
      }
    }
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i) {
      const int32_t f = free_[i];
      if (f < 0) continue;
      const int32_t row = cholesky_.permutation()[f];
      X_(row, 0) = rhs_[i].x();
      X_(row, 1) = rhs_[i].y();
      X_(row, 2) = rhs_[i].z();
    }
  }

  // The system matrix with the contact term on the particles in held_now_ (its pattern, and so
  // the permutation, never changes: only the diagonal does).
  void refactorise() {
    held_ = held_now_;
    for (int32_t i = 0; i < static_cast<int32_t>(free_.size()); ++i) {
      const int32_t f = free_[i];
      if (f >= 0)
        cholesky_.values()[diag_at_[f]] = diagonal_[f] + (held_[i] ? contact_weight_ : 0.0);
    }
    if (!cholesky_.factorise())
      throw InputError("solver.method",
                       "the fast method could not factorise its system matrix (masses must be "
                       "positive)");
  }

  // 3. Global step: L·Lᵀ·(P·x) = P·b, the three coordinates side by side in one pass over the
  // factor, in place. The result stays permuted: unknown f is row permutation()[f]. (One
  // coordinate a thread read the factor three times, twice on one thread with two threads: on
  // 128² denim these solves were nearly all of an iteration.)
  void global_solve() {
    if (free_count_ == 0) return;
    cholesky_.solve3_in_place(X_);
  }

  // The local/global iteration replaces each spring's Hessian k·d̂d̂ᵀ by k·I, so the error in
  // the directions it gets wrong shrinks per iteration by about h²K/(m + h²K), with K the
  // largest total stiffness at a free particle (Gershgorin) and m its mass: the spectral
  // radius Chebyshev needs (Wang 2015 estimates it by running the solver; this bound is
  // cheap and errs high only by the transverse stiffness it ignores).
  static double estimate_rho(const World& w, double h) {
    const ClothModel& m = w.model;
    const std::vector<double> k_sum = spring_sums(m, &Spring::stiffness);
    double rho = 0.0;
    for (int32_t i = 0; i < m.size(); ++i) {
      if (w.state.inv_mass[i] == 0.0) continue;
      const double a = h * h * k_sum[i] * w.state.inv_mass[i];
      rho = std::max(rho, a / (1.0 + a));
    }
    return std::min(rho, 0.9999);
  }

  double chebyshev_weight(int it, double omega) const {
    if (rho_ <= 0.0 || it < kChebyshevDelay) return 1.0;
    if (it == kChebyshevDelay) return 2.0 / (2.0 - rho_ * rho_);
    return 4.0 / (4.0 - rho_ * rho_ * omega);
  }

  SolverDef def_;  // as prepared (build() may take more substeps for a frame)
  int substeps_ = 1;
  int iterations_ = kDefaultIterations;
  double rho_ = 0.0;
  double h_ = 1.0 / 60.0;
  bool compressed_soft_ = false;  // the model's compressed springs act with less stiffness
  bool damped_along_ = false;     // springs damp the move along them only (a material's)
  double contact_weight_ = 0.0;   // kg, w of the contact term (0 without colliders)
  int32_t free_count_ = 0;
  std::vector<int32_t> free_;  // particle → unknown, −1 when fixed
  // M + hC + h²L, plus w on the held particles, and its factor.
  SparseCholesky cholesky_;
  std::vector<int64_t> diag_at_;  // unknown → its diagonal entry in cholesky_.values()
  Eigen::VectorXd diagonal_;      // the diagonal without the contact term
  std::vector<char> held_;        // 1: the particle carries the contact term in the factor
  std::vector<char> held_now_;    // the same for this substep, decided in inertia()
  SparseCholesky::Rows3 X_;       // the global step's unknowns, x, y and z of each side by side
  std::vector<Vec3> x0_, y_, xk_, xkm1_, b0_, rhs_, force_;
  std::vector<Vec3> contact_n_;          // outward normal of the particle's contact
  std::vector<Vec3> contact_surface_;    // the velocity of the surface it touches (m/s)
  std::vector<double> contact_dvn_;      // its normal velocity change (m/s), 0 = no contact
  std::vector<double> contact_mu_;       // its friction coefficient
  std::vector<double> contact_gripped_;  // the part of its friction the solve used, 0…1
};

}  // namespace

std::unique_ptr<Solver> make_fast() {
  return std::make_unique<Fast>();
}

}  // namespace drape
