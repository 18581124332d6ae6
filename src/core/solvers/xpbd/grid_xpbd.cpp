// `xpbd`: extended position-based dynamics with small steps (Macklin, Müller & Chentanez
// 2016, "XPBD"; Macklin et al. 2019, "Small steps in physics simulation"), written for the
// cloth's regular grid. Per substep: predict with the external forces, project the springs as
// compliant distance constraints (α = 1/k, damping from the spring's c) by Gauss–Seidel colour
// by colour, sweep the stiffest springs again with the contacts if asked (solver.stiff_sweeps),
// apply long-range attachments, resolve contacts on positions, derive v = (x − x_prev)/h.
// With solver.line_passes the structural springs are not swept one by one: each row and each
// column of them is one chain, solved exactly per pass (see "Line passes" below), and the stiff
// sweeps, if asked, sweep them after the passes.
//
// The state is kept as structure-of-arrays in a layout where every row holds its columns
// grouped by residue mod 4 (GridLayout), and a family of springs (one direction of one kind)
// is swept row by row: whatever the direction, a row's springs of one colour are then a few
// contiguous runs, so the inner loops vectorise without gathers. Rows are split between
// threads; a colour's springs share no particle, so the result has the same bits for any
// thread count (and for any order inside a colour, layout included). Each position is held as
// its base (where the particle stood at the substep's start) plus its move since, so spring
// vectors and velocities (move/h) keep their own precision rather than that of |x|: in single
// precision (solver.precision) a step's move stays visible however small it is next to |x|.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "chains.h"
#include "constraints.h"
#include "lanes.h"
#include "largest_coordinate.h"
#include "particles.h"
#include "xpbd.h"

namespace drape::xpbd {

namespace {

/// Where a particle lives in the solver's arrays. Each row is padded to four blocks of equal
/// length holding the columns c ≡ 0, 1, 2, 3 (mod 4), in order. A spring from column c to
/// column c + dc with |dc| ≤ 3 then joins slot k of one block to slot k (or k ± 1) of another,
/// so the springs whose first column has one residue run contiguously at both ends. Padding
/// slots carry no particle: zero inverse mass and no spring.
struct GridLayout {
  int cols = 0, rows = 0;
  int block = 0;   ///< slots per residue block: ceil(cols / 4)
  int stride = 0;  ///< slots per row: 4·block

  void prepare(int c, int r) {
    cols = c;
    rows = r;
    block = (c + 3) / 4;
    stride = 4 * block;
  }
  int32_t size() const { return rows * stride; }
  int32_t index(int r, int c) const { return r * stride + (c & 3) * block + (c >> 2); }
  /// The slot of particle i (row-major index in the cloth).
  int32_t slot(int32_t i) const { return index(i / cols, i % cols); }
};

/// One family of fine springs: from (c, r) to (c + dc, r + dr), all of one kind, with one rest
/// length, stiffness and damping (build_grid makes them so; prepare() checks).
struct Family {
  int dc = 0, dr = 0;  ///< dr ≥ 0; dr = 0 means dc > 0
  int shift = 0;       ///< for dc < 0, the spring starts at column c + 1: (c + 1, r)–(c, r + 1)
  double rest = 0.0, stiffness = 0.0, damping = 0.0;
  SpringKind kind = SpringKind::structural;
};

template <typename Real>
class GridXpbd final : public Solver {
  using Lane = typename Lanes<Real>::Vec;
  using ChainRow = ChainRowOf<Real>;

 public:
  void prepare(const World& w, const SolverDef& def) override {
    const ClothModel& m = w.model;
    cols_ = m.grid.cols;
    rows_ = m.grid.rows;
    grid_.prepare(cols_, rows_);
    triangles_.clear();
    const int32_t n = m.size(), slots = grid_.size();
    // Padding slots stay at zero: they never move. The slack is for Lanes::load.
    particles_.resize(slots, Lanes<Real>::kLanes);
    scratch_.assign(n, Vec3::Zero());
    prepare_families(m);
    stiffest_ = 0.0;
    for (const Family& f : families_) stiffest_ = std::max(stiffest_, f.stiffness);
    iterations_ = def.iterations > 0 ? def.iterations : kDefaultIterations;
    stiff_sweeps_ = def.stiff_sweeps;
    lambda_.assign(iterations_ > 1 ? families_.size() * static_cast<size_t>(slots) : 0, 0.0);
    attached_ = w.attachments.active();
    particles_.prepare_attachments(w.attachments, n, [&](int32_t i) { return grid_.slot(i); });
    particles_.area_drag(w.area_drag());
    prepare_lines(w, def);
    current_ = false;
    frame_dt_ = def.dt;
    if (def.substeps > 0) {
      substeps_ = def.substeps;
      return;
    }
    // Structural springs solved as chains need no substeps for their stiffness.
    substeps_ = automatic_substeps(
        w, def, [&](const Spring& s) { return !(lines_ && s.kind == SpringKind::structural); });
  }

  void state_changed() override {
    current_ = false;
  }

  void step_frame(World& w, double dt) override {
    // A part of a frame takes its share of the substeps, but with line passes all of them:
    // the passes are what undoes the stretch self-collision's pushes leave between parts, and
    // fewer of them left a pile's threads 41-59% stretched at 128² (README, Self-collision).
    const int steps = lines_ ? substeps_ : substeps_in(dt, frame_dt_, substeps_);
    const double h = dt / steps;
    ClothState& s = w.state;
    const ClothModel& m = w.model;
    const int32_t n = m.size();
    // External acceleration, held over the frame: gravity plus the wind at the frame's start.
    // The wind does not depend on the substep's positions, so it is as stable at the frame
    // step as gravity, and evaluating it once keeps many substeps cheap.
    // Drag on the area (forces.air_density) with the frame's normals, as the wind.
    const bool wind = w.forces.wind.strength > 0.0 && w.forces.wind.coefficient > 0.0;
    const bool area = w.area_drag();
    if (wind || area) update_normals(m, s);
    if (wind) {
      std::fill(scratch_.begin(), scratch_.end(), Vec3::Zero());
      forces::add_wind(m, s, w.forces.wind, w.time, scratch_);
    }
    const double half_rho_c = 0.5 * w.air_density() * w.forces.drag_coefficient;
    const Vec3 g = w.forces.gravity;
    const double drag = w.air_drag();
    const bool read = !current_;
    particles_.read_pins(s, w.attachments);
    if (w.colliders_move() && triangles_.empty())
      triangles_ = triangle_slots(m, [&](int32_t i) { return grid_.slot(i); });
    const bool triangles = w.colliders_move();

#pragma omp parallel if (worth_threads(n))
    {
      // The state is read only where the arrays do not hold it already (see current_); the
      // wind's acceleration is new every frame.
      if (read || wind || area) {
#pragma omp for schedule(static)
        for (int32_t i = 0; i < n; ++i) {
          particles_.read(s, i, grid_.slot(i), wind ? Vec3(g + s.inv_mass[i] * scratch_[i]) : g,
                          read);
          if (area) particles_.read_area(m, s, half_rho_c, i, grid_.slot(i));
        }
      }
      for (int k = 0; k < steps; ++k) {
        if (!substep_begins(w, k, h, stopping_)) break;
        particles_.predict(h, drag);
        for (int it = 0; it < iterations_; ++it) project_springs(h, it);
        if (lines_) {
          for (int pass = 0; pass < line_passes_; ++pass)
            solve_lines(w.colliders, h, pass == 0, pass + 1 < line_passes_ ? relaxation_ : 1);
          for (int it = 0; it < stiff_sweeps_; ++it) sweep_chains(w.colliders, h);
        } else {
          for (int it = 0; it < stiff_sweeps_; ++it) {
            if (it % kContactEvery == 0 && !w.colliders.empty()) resolve_contacts(w.colliders);
            project_stiffest(h);
          }
          if (attached_) apply_attachments();
        }
        finish_substep(w.colliders, h, triangles, w.features,
                       w.held && HeldLayers::due(k, steps) ? w.held : nullptr);
      }
#pragma omp for schedule(static)
      for (int32_t i = 0; i < n; ++i) particles_.write(s, i, grid_.slot(i));
    }
    update_normals(m, s);
    current_ = true;
  }

  bool holds_layers() const override {
    return true;
  }
  int substeps() const override {
    return substeps_;
  }
  int64_t workspace_bytes() const override {
    return particles_.bytes() +
           heap_bytes(scratch_, triangles_, families_, lambda_, col_slot_, row_fixed_, col_fixed_,
                      fixed_columns_, rows_n_.x, rows_n_.y, rows_n_.z, rows_b_, rows_r_, rows_dl_,
                      twist_beta_, twist_g_, twist_fe_, twist_fg_, twist_dl_) +
           row_chains_.bytes() + col_chains_.bytes();
  }

 private:
  // ---- Set-up --------------------------------------------------------------------------------

  // Groups the model's springs into families by direction and kind, and checks that each family
  // is uniform (the grid builder makes it so; a model that is not would be a programming error).
  // Rest lengths are uniform to the rounding of the positions they are measured between: a
  // micrometre cloth 2 m from the origin has its rest lengths differ in the eighth digit.
  void prepare_families(const ClothModel& m) {
    families_.clear();
    std::vector<int64_t> counts;
    const double rounding =
        16.0 * std::numeric_limits<double>::epsilon() * largest_coordinate(m.rest_position);
    for (const Spring& sp : m.springs) {
      const int ci = sp.i % cols_, ri = sp.i / cols_, cj = sp.j % cols_, rj = sp.j / cols_;
      Family f;
      f.dc = cj - ci;
      f.dr = rj - ri;
      if (f.dr < 0 || (f.dr == 0 && f.dc <= 0))
        throw std::logic_error("xpbd: spring not in grid order");
      f.shift = f.dc < 0 ? -f.dc : 0;
      f.rest = sp.rest;
      f.stiffness = sp.stiffness;
      f.damping = sp.damping;
      f.kind = sp.kind;
      auto same = [&](const Family& o) { return o.dc == f.dc && o.dr == f.dr; };
      auto it = std::find_if(families_.begin(), families_.end(), same);
      if (it == families_.end()) {
        families_.push_back(f);
        counts.push_back(1);
      } else {
        if (std::abs(it->rest - f.rest) > 1e-12 * f.rest + rounding ||
            it->stiffness != f.stiffness || it->damping != f.damping || it->kind != f.kind)
          throw std::logic_error("xpbd: springs of one grid direction differ");
        ++counts[it - families_.begin()];
      }
    }
    // Every spring of a family must be present for the row loops to be right, and its
    // direction one that GridLayout keeps contiguous and the colouring keeps independent.
    for (size_t k = 0; k < families_.size(); ++k) {
      const Family& f = families_[k];
      if (std::abs(f.dc) > 3 || (f.dr == 0 && f.dc > 2))
        throw std::logic_error("xpbd: spring direction not supported by the grid layout");
      const int64_t expected = int64_t{cols_ - std::abs(f.dc)} * (rows_ - f.dr);
      if (counts[k] != expected) throw std::logic_error("xpbd: grid family incomplete");
    }
  }

  // Line passes: which families are the chains, the layout's tables, the fixed chains and the
  // scratch. They run only when nothing is fixed but what attachments hold (the pins, with
  // cloth.long_range): scene files are checked for that, but a particle held by the hand is
  // fixed too, and while it is held the structural springs are swept one by one instead.
  void prepare_lines(const World& w, const SolverDef& def) {
    const ClothModel& m = w.model;
    line_passes_ = def.line_passes;
    relaxation_ = static_cast<Real>(def.line_relaxation);
    row_family_ = col_family_ = -1;
    for (size_t k = 0; k < families_.size(); ++k) {
      const Family& f = families_[k];
      const bool structural = f.kind == SpringKind::structural && f.stiffness > 0.0;
      if (f.dc == 1 && f.dr == 0 && structural) row_family_ = static_cast<int>(k);
      if (f.dc == 0 && f.dr == 1 && structural) col_family_ = static_cast<int>(k);
    }
    int32_t fixed = 0;
    for (int32_t i = 0; i < m.size(); ++i) fixed += w.state.inv_mass[i] == 0.0;
    const bool held = fixed > static_cast<int32_t>(w.attachments.pins().size());
    lines_ = line_passes_ > 0 && row_family_ >= 0 && col_family_ >= 0 && !held;
    if (!lines_) return;
    col_slot_.resize(cols_);
    for (int c = 0; c < cols_; ++c) col_slot_[c] = grid_.index(0, c);
    // A chain through a fixed particle is swept spring by spring: between two pins a row is a
    // taut string, whose exact solve is near singular.
    row_fixed_.assign(rows_, 0);
    col_fixed_.assign(grid_.stride, 0);
    for (int32_t i = 0; i < m.size(); ++i) {
      if (w.state.inv_mass[i] != 0.0) continue;
      row_fixed_[i / cols_] = 1;
      col_fixed_[col_slot_[i % cols_]] = 1;
    }
    // Each direction its own arrays: rows and columns are shared out to threads differently,
    // and scratch that changed hands every pass would cross between the cores' caches.
    row_chains_.prepare(size_t(cols_ + 1) * row_groups());
    col_chains_.prepare(size_t(rows_ + 1) * grid_.stride);
    fixed_columns_.clear();
    for (int l = 0; l < grid_.stride; ++l)
      if (col_fixed_[l]) fixed_columns_.push_back(l);
    twist_ = twist_row();
    for (AlignedVector<Real>* a : {&twist_beta_, &twist_g_, &twist_fe_, &twist_fg_, &twist_dl_})
      a->assign(grid_.stride, 0.0);
    const int32_t slots = grid_.size();
    const int32_t slack = Lanes<Real>::kLanes;  // for Lanes::load
    rows_n_.resize(slots + slack);
    rows_b_.assign(slots + slack, 1.0);
    rows_r_.assign(slots + slack, 0.0);
    rows_dl_.assign(slots, 0.0);
  }

  // ---- The substep (all called inside one parallel region) -----------------------------------

  // One Gauss–Seidel sweep over every fine spring, family by family and colour by colour.
  void project_springs(Real h, int iteration) {
    for (size_t k = 0; k < families_.size(); ++k) {
      if (families_[k].stiffness <= 0.0) continue;  // infinite compliance: no constraint
      if (lines_ && (int(k) == row_family_ || int(k) == col_family_)) continue;  // solved as chains
      sweep_colours(families_[k], h, lambda_.empty() ? nullptr : lambda_.data() + k * grid_.size(),
                    iteration == 0);
    }
  }

  // One more sweep of the stiffest families only (solver.stiff_sweeps). With one sweep per
  // substep every spring much stiffer than m/h² acts alike, about as stiff as m/h² allows, and
  // the softer families, swept after the stiffest, leave them stretched at the substep's end:
  // cloth forced to shear (draped over a sphere) stretches its structural springs as much as its
  // shear springs. Sweeping the stiffest again restores their precedence. These sweeps start
  // from λ = 0 (a plain projection with the spring's compliance and damping).
  void project_stiffest(Real h) {
    if (stiffest_ <= 0.0) return;  // no spring has stiffness: nothing to sweep
    for (const Family& f : families_)
      if (f.stiffness >= stiffest_) sweep_colours(f, h, nullptr, true);
  }

  // With line passes the stiff sweeps come after them, over the chains' springs (the
  // structural ones) spring by spring from λ = 0, each after the attachments and contacts as a
  // pass is. The passes remove what is smooth along the chains, but at the crests of folds,
  // where rows and columns pull across each other, the rows, solved first, are left stretched
  // by the columns solved after, and where cloth gathers on the sphere friction holds a few
  // springs compressed. Both are local, which sweeps take out at a fraction of a pass's cost.
  // A sweep goes the other way round, columns then rows, so that the rows have the last word
  // (symmetric Gauss–Seidel). Over the last second of bench drape at 4 substeps of 4 passes in
  // single precision the largest strain, stretch or compression, was 1.12% at 256² and 1.33% at
  // 128²; one sweep after the passes left 0.59% and 0.88%, a fifth pass instead 0.82% and
  // 0.59%. Rows then columns left 0.61% and 1.05%; rows alone failed a hanging cloth, whose
  // columns carry its weight (hang-lr-256 at 4 substeps of 3 passes and a sweep: 1.6%).
  void sweep_chains(const std::vector<Collider>& colliders, Real h) {
    if (attached_ || !colliders.empty()) {  // else a barrier for nothing
#pragma omp for schedule(static)
      for (int r = 0; r < rows_; ++r) constrain_row(colliders, r);
    }
    sweep_colours(families_[col_family_], h, nullptr, true);
    sweep_colours(families_[row_family_], h, nullptr, true);
  }

  // A family's compliance for a substep of h.
  static Compliance<Real> compliance(const Family& f, Real h) {
    return Compliance<Real>::of(f.stiffness, f.damping, h);
  }

  // Both colours of family f in a substep of h; with λ (several iterations) accumulated in
  // `lambda`, from zero when `first`.
  void sweep_colours(const Family& f, Real h, Real* lambda, bool first) {
    const Compliance<Real> compliance_h = compliance(f, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    for (int colour = 0; colour < 2; ++colour) {
      if (lambda == nullptr)
        sweep_family<false>(f, colour, alpha_tilde, gamma, nullptr, true);
      else
        sweep_family<true>(f, colour, alpha_tilde, gamma, lambda, first);
    }
  }

  // The springs of family f from row r to row r + f.dr whose first column is ≡ b (mod 4): for
  // k in [k_begin, k_end), column 4k + b at slot i0 + k and its partner at slot j0 + k.
  struct Run {
    int i0, j0, k_begin, k_end;
  };
  Run run_of(const Family& f, int r, int b) const {
    // Columns cs = 4k + b in [shift, shift + span), partners cs + dc at residue b2, slot k + carry.
    const int span = cols_ - std::abs(f.dc);
    const int t = b + f.dc + 4, b2 = t & 3, carry = t / 4 - 1;
    return {r * grid_.stride + b * grid_.block,
            (r + f.dr) * grid_.stride + b2 * grid_.block + carry,
            std::max(0, (f.shift - b + 3) / 4), std::max(0, (f.shift + span - b + 3) / 4)};
  }

  // The springs of family f whose colour is `colour`: for dr > 0 the rows r with (r / dr) even
  // or odd; for dr = 0 the springs whose first column c has (c / dc) even or odd, which for
  // dc ≤ 2 depends on c mod 4 alone. Springs are indexed for λ by their first particle's slot.
  template <bool kLambda>
  void sweep_family(const Family& f, int colour, Real alpha_tilde, Real gamma,
                    Real* __restrict lambda, bool first) {
    const Real *__restrict bx = particles_.base.x.data(), *__restrict by = particles_.base.y.data(),
                           *__restrict bz = particles_.base.z.data();
    Real *__restrict mx = particles_.move.x.data(), *__restrict my = particles_.move.y.data(),
                     *__restrict mz = particles_.move.z.data();
    const Real* __restrict w = particles_.inv_mass.data();
    const Real rest = f.rest;
    // λ is kept only when several iterations need it; with one it is 0 at the start.
    auto one = [&](int i, int j) {
      if constexpr (kLambda) {
        const Real l0 = first ? Real(0) : lambda[i];
        lambda[i] = l0 + xpbd_project<false, true>(bx, by, bz, mx, my, mz, w, i, j, rest,
                                                   alpha_tilde, gamma, l0);
      } else {
        xpbd_project<false, true>(bx, by, bz, mx, my, mz, w, i, j, rest, alpha_tilde, gamma,
                                  Real(0));
      }
    };
    auto run = [&](int r, int b) {
      const Run u = run_of(f, r, b);
#pragma omp simd
      for (int k = u.k_begin; k < u.k_end; ++k) one(u.i0 + k, u.j0 + k);
    };
    if (f.dr > 0) {
      const int bands = (rows_ - f.dr + f.dr - 1) / f.dr;  // row bands of height dr
      // Band b covers rows [b·dr, b·dr + dr); colour = b mod 2.
#pragma omp for schedule(static)
      for (int band = colour; band < bands; band += 2)
        for (int r = band * f.dr; r < std::min((band + 1) * f.dr, rows_ - f.dr); ++r)
          for (int b = 0; b < 4; ++b) run(r, b);
    } else {
#pragma omp for schedule(static)
      for (int r = 0; r < rows_; ++r)
        for (int b = 0; b < 4; ++b)
          if (((b / f.dc) & 1) == colour) run(r, b);
    }
  }

  // ---- Line passes ---------------------------------------------------------------------------
  //
  // A row of structural springs is a chain of constraints t = 0 … n−2 between its particles
  // t and t + 1, and its XPBD step (Macklin et al. 2016, eq. 26) linearised at the current
  // positions is one tridiagonal system in the multipliers' changes Δλ:
  //   ((1 + γ)·J W Jᵀ + α̃) Δλ = −C − α̃·λ − γ·J·(x − x_prev),
  //   (J W Jᵀ)_t,t = w_t + w_t+1,   (J W Jᵀ)_t−1,t = −w_t·(n_t−1 · n_t),
  // n_t the unit direction of constraint t; then x += W Jᵀ Δλ. Solved exactly (the Thomas
  // algorithm, linear in n) it is one Newton step on the whole chain: a stretch is removed along
  // the row in one pass rather than creeping a spring further per Gauss–Seidel sweep, so the
  // passes a cloth needs do not grow with its resolution. (Goldenthal et al. 2007 solve every
  // inextensibility constraint of a cloth so, with a sparse direct solver; rows and columns are
  // the grid's tridiagonal blocks of that system.) All rows are solved, then all columns: block
  // Gauss–Seidel between the two. Every pass but the last is over-relaxed by ω
  // (solver.line_relaxation; block SOR): each chain's Δλ, and so its moves, times ω. A chain's
  // own error is then overshot by ω − 1, which the next pass takes back, while what block
  // Gauss–Seidel removes slowly, the coupling of rows and columns through the contacts and the
  // cloth's folds, goes faster; the last pass is plain, so that the chains end solved. Columns are
  // vectorised across columns (a row's slots are contiguous); rows along each row where they can
  // be, and across rows in the recurrences.

  // A constraint of a chain through a fixed particle is swept spring by spring instead, twice per
  // pass, red–black: between two pins a row is a taut string whose exact solve is near singular.
  static constexpr int kFixedChainSweeps = 2;

  // The rows in groups of Lanes<Real>::kLanes, the last one filled up with lanes that do nothing.
  int row_groups() const {
    return (rows_ + Lanes<Real>::kLanes - 1) / Lanes<Real>::kLanes;
  }

  // One pass: the attachments and contacts, every row, then every column, each thread its share
  // of them. A thread resolves the attachments and contacts of its own rows and solves those
  // rows at once, with no barrier between: a row's attachments and contacts move its own
  // particles only, and read the pins from pin_at_, not from the arrays other threads write.
  void solve_lines(const std::vector<Collider>& colliders, Real h, bool first, Real omega) {
    const Family& rf = families_[row_family_];
    const Family& cf = families_[col_family_];
    const int parts = team_size();
#pragma omp for schedule(static)
    for (int part = 0; part < parts; ++part) {
      const int g0 = part_group(part, parts), g1 = part_group(part + 1, parts);
      for (int r = group_row(g0); r < group_row(g1); ++r) constrain_row(colliders, r);
      solve_rows(rf, h, g0, g1, first, omega);
    }
    if (rows_ < 2) return;  // no columns
    // Each half's columns shared out, so that with two threads each has one half.
    const int ranges = std::max(1, parts / 2), stride = grid_.stride;
#pragma omp for schedule(static)
    for (int item = 0; item < 2 * ranges; ++item) {
      const int r = item % ranges;
      eliminate_columns(cf, h, item / ranges, stride * r / ranges, stride * (r + 1) / ranges,
                        first);
    }
#pragma omp for schedule(static)
    for (int item = 0; item < 2 * ranges; ++item) {
      const int r = item % ranges;
      substitute_columns(item / ranges, stride * r / ranges, stride * (r + 1) / ranges, first,
                         omega);
    }
    if (!fixed_columns_.empty()) sweep_fixed_columns(cf, h, parts);
  }

  // The first lane group of the rows that `part` of `parts` solves (row_groups() for
  // part = parts): the one split of the rows between threads, which the columns' twist, the
  // fixed columns' sweeps and the attachments and contacts of each pass follow.
  int part_group(int part, int parts) const {
    return row_groups() * part / parts;
  }

  // The first row of lane group G (rows_ for G = row_groups()).
  int group_row(int G) const {
    return std::min(G * Lanes<Real>::kLanes, rows_);
  }

  // The attachments and contacts of row r, as each pass starts.
  void constrain_row(const std::vector<Collider>& colliders, int r) {
    if (attached_) attachments_row(r);
    contacts_row(colliders, r);
  }

  // The columns are solved from both ends at once (a twisted factorisation, as in the "burn at
  // both ends" Thomas algorithm): the top half of every column is eliminated downwards and the
  // bottom half upwards, both meet at the twist, constraint twist_ between particle rows twist_
  // and twist_ + 1, whose Δλ both halves then compute alike, and each half substitutes back
  // outwards from it. A half moves only its own particles, the rows the row solve gives the
  // same thread with two threads: split down the columns instead, every pass would carry half
  // the cloth's moves from one core's cache to the other's and back, which made a second
  // thread gain nothing on the columns at 128² and 256². Vectorised across columns (a row's
  // slots are contiguous). Constraint t of column l (rows t and t + 1) has entry
  // (t + 1)·stride + l, the slot of particle t + 1; entry l (before the first) and the one after
  // the last stay zero and end the recurrences.

  // The twist: the constraint below the rows the row solve gives the first of two threads, so
  // that each half moves the particles its thread solves the rows of; a row at least each side
  // (0 for a single row, which has no column constraints).
  int twist_row() const {
    if (rows_ < 2) return 0;
    return std::clamp(group_row(part_group(1, 2)), 1, rows_ - 1) - 1;
  }

  // Elimination towards the twist of half `half` (0 the top, 1 the bottom) of the columns whose
  // slot in a row is in [l0, l1).
  void eliminate_columns(const Family& f, Real h, int half, int l0, int l1, bool first) {
    const int stride = grid_.stride, k = twist_;
    const unsigned char* __restrict fixed = col_fixed_.data();
    const Real *__restrict bx = particles_.base.x.data(), *__restrict by = particles_.base.y.data(),
                           *__restrict bz = particles_.base.z.data();
    const Real *__restrict mx = particles_.move.x.data(), *__restrict my = particles_.move.y.data(),
                           *__restrict mz = particles_.move.z.data();
    ChainScratch<Real>& cs = col_chains_;
    Real *__restrict nx = cs.n.x.data(), *__restrict ny = cs.n.y.data(),
                     *__restrict nz = cs.n.z.data();
    Real *__restrict fe = cs.f.data(), *__restrict g = cs.g.data(),
                     *__restrict inv_beta = cs.inv_beta.data();
    const Real* __restrict lambda = cs.lambda.data();
    Real *__restrict twist_beta = twist_beta_.data(), *__restrict twist_g = twist_g_.data(),
                     *__restrict twist_fe = twist_fe_.data(),
                     *__restrict twist_fg = twist_fg_.data();
    const Real* __restrict w = particles_.inv_mass.data();
    const Compliance<Real> compliance_h = compliance(f, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    const Real rest = f.rest, keep = first ? Real(0) : Real(1);
    if (half == 0) {
      // Downwards, constraint t after t − 1 sharing particle t; at the twist only its pivot and
      // right side, kept for the twist's solve.
      for (int t = 0; t <= k; ++t) {
#pragma omp simd
        for (int l = l0; l < l1; ++l) {
          const int i = t * stride + l, q = i + stride;  // particle (t, l), (t + 1, l); entry
          const ChainRow c =
              chain_row(bx, by, bz, mx, my, mz, w, i, q, !fixed[l], rest, alpha_tilde, gamma);
          const Real alpha_lambda = alpha_tilde * keep * lambda[q];
          if (t < k) {
            eliminate(c, w[i], gamma, alpha_lambda, nx, ny, nz, fe, g, inv_beta, i, q, q);
          } else {
            const auto [e, fd] = pivot(c, w[i], gamma, nx, ny, nz, inv_beta, i);
            nx[q] = c.nx;
            ny[q] = c.ny;
            nz[q] = c.nz;
            fe[q] = fd;
            twist_beta[l] = c.b - fd * e;
            twist_g[l] = c.r - alpha_lambda - fd * g[i];
          }
        }
      }
      return;
    }
    // Upwards, constraint t after t + 1 sharing particle t + 1, whose e/β goes to entry t + 1
    // (for the substitution downwards); at the twist only what the bottom adds to its pivot and
    // right side.
    for (int t = rows_ - 2; t >= k; --t) {
#pragma omp simd
      for (int l = l0; l < l1; ++l) {
        const int i = t * stride + l, q = i + stride, p = q + stride;
        const ChainRow c =
            chain_row(bx, by, bz, mx, my, mz, w, i, q, !fixed[l], rest, alpha_tilde, gamma);
        if (t > k) {
          eliminate(c, w[q], gamma, alpha_tilde * keep * lambda[q], nx, ny, nz, fe, g, inv_beta, p,
                    q, p);
        } else {
          const auto [e, fu] = pivot(c, w[q], gamma, nx, ny, nz, inv_beta, p);
          fe[p] = fu;
          twist_fe[l] = fu * e;
          twist_fg[l] = fu * g[p];
        }
      }
    }
  }

  // The twist's Δλ, then the substitution outwards of half `half` and its particles' moves.
  void substitute_columns(int half, int l0, int l1, bool first, Real omega) {
    const int stride = grid_.stride, k = twist_, last = rows_ - 1;
    Real *__restrict mx = particles_.move.x.data(), *__restrict my = particles_.move.y.data(),
                     *__restrict mz = particles_.move.z.data();
    ChainScratch<Real>& cs = col_chains_;
    const Real *__restrict nx = cs.n.x.data(), *__restrict ny = cs.n.y.data(),
                           *__restrict nz = cs.n.z.data();
    const Real *__restrict fe = cs.f.data(), *__restrict inv_beta = cs.inv_beta.data();
    Real *__restrict g = cs.g.data(), *__restrict lambda = cs.lambda.data();
    const Real *__restrict twist_beta = twist_beta_.data(), *__restrict twist_g = twist_g_.data(),
                           *__restrict twist_fe = twist_fe_.data(),
                           *__restrict twist_fg = twist_fg_.data();
    Real* __restrict twist_dl = twist_dl_.data();
    const Real* __restrict w = particles_.inv_mass.data();
    const Real keep = first ? Real(0) : Real(1);
    auto move = [&](int i, Real ax, Real ay, Real az) {
      mx[i] += w[i] * ax;
      my[i] += w[i] * ay;
      mz[i] += w[i] * az;
    };
    if (half == 0) {
#pragma omp simd
      for (int l = l0; l < l1; ++l) {
        const int q = (k + 1) * stride + l;
        take(g, lambda, keep, omega, q, (twist_g[l] - twist_fg[l]) / (twist_beta[l] - twist_fe[l]));
      }
      for (int t = k - 1; t >= 0; --t) {
#pragma omp simd
        for (int l = l0; l < l1; ++l) {
          const int q = (t + 1) * stride + l, qn = q + stride;  // also particle t + 1 and t + 2
          const Real dl = omega * substitute(g, inv_beta, lambda, keep, omega, q, fe[qn], g[qn]),
                     dn = omega * g[qn];
          move(q, nx[q] * dl - nx[qn] * dn, ny[q] * dl - ny[qn] * dn, nz[q] * dl - nz[qn] * dn);
        }
      }
#pragma omp simd
      for (int l = l0; l < l1; ++l) {  // the top particle
        const int q = stride + l;
        const Real dl = omega * g[q];
        move(l, -nx[q] * dl, -ny[q] * dl, -nz[q] * dl);
      }
      return;
    }
#pragma omp simd
    for (int l = l0; l < l1; ++l)
      twist_dl[l] = (twist_g[l] - twist_fg[l]) / (twist_beta[l] - twist_fe[l]);
    // Δλ of constraint t − 1: the twist's own copy for the first, so as not to read what the
    // top half writes meanwhile.
    auto previous = [&](int t) { return t == k + 1 ? twist_dl : g + t * stride; };
    for (int t = k + 1; t < last; ++t) {
      const Real* __restrict dp = previous(t);
#pragma omp simd
      for (int l = l0; l < l1; ++l) {
        const int q = (t + 1) * stride + l, qp = q - stride;  // also particle t + 1 and t
        const Real dl = substitute(g, inv_beta, lambda, keep, omega, q, fe[q], dp[l]);
        const Real a = omega * dp[l], b = omega * dl;
        move(qp, nx[qp] * a - nx[q] * b, ny[qp] * a - ny[q] * b, nz[qp] * a - nz[q] * b);
      }
    }
    const Real* __restrict dp = previous(last);
#pragma omp simd
    for (int l = l0; l < l1; ++l) {  // the bottom particle
      const int qp = last * stride + l;
      const Real a = omega * dp[l];
      move(qp, nx[qp] * a, ny[qp] * a, nz[qp] * a);
    }
  }

  // The rows of lane groups [g0, g1) (rows L·g0 up to L·g1, or the last row). What costs
  // (directions, square roots) and the moves run along each row in its contiguous runs of one
  // column residue, as the spring sweeps do, by slot into rows_n_, rows_b_, rows_r_, rows_dl_.
  // The recurrences run across rows, a lane a row, on tiles of those arrays transposed (Lanes):
  // constraint t of the rows of group G has entry G·(cols + 1) + t + 1, so a group's entries are
  // contiguous and each thread's groups one block. Laid out constraint-major instead, with the
  // groups of both threads side by side, the recurrences took as long on half the rows with two
  // threads as on all of them with one (drape-128, 4 + 4 + 1 single: 0.71 ms a frame either way).
  void solve_rows(const Family& f, Real h, int g0, int g1, bool first, Real omega) {
    constexpr int L = Lanes<Real>::kLanes;
    const int r0 = group_row(g0), r1 = group_row(g1), stride = grid_.stride;
    const int block = grid_.block, entries = cols_ + 1;
    const unsigned char* __restrict fixed = row_fixed_.data();
    const Real *__restrict bx = particles_.base.x.data(), *__restrict by = particles_.base.y.data(),
                           *__restrict bz = particles_.base.z.data();
    Real *__restrict mx = particles_.move.x.data(), *__restrict my = particles_.move.y.data(),
                     *__restrict mz = particles_.move.z.data();
    Real *__restrict sx = rows_n_.x.data(), *__restrict sy = rows_n_.y.data(),
                     *__restrict sz = rows_n_.z.data(), *__restrict sb = rows_b_.data(),
                     *__restrict sr = rows_r_.data(), *__restrict sdl = rows_dl_.data();
    ChainScratch<Lane>& cs = row_chains_;
    Lane *__restrict nx = cs.n.x.data(), *__restrict ny = cs.n.y.data(),
                     *__restrict nz = cs.n.z.data();
    Lane *__restrict fe = cs.f.data(), *__restrict g = cs.g.data(),
                     *__restrict inv_beta = cs.inv_beta.data();
    Lane* __restrict lambda = cs.lambda.data();
    const Real* __restrict w = particles_.inv_mass.data();
    const Compliance<Real> compliance_h = compliance(f, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    const Real rest = f.rest, keep = first ? Real(0) : Real(1);
    // Each constraint's direction, diagonal and right-hand side, by its first particle's slot.
    // Each run goes on to the end of its block (k < block, not u.k_end): in the block of the
    // last column, a constraint from it (or from padding) to the next block's first slot, which
    // the recurrences never read and whose Δλ is 0. Full blocks vectorise without a scalar
    // remainder, which took a tenth of the row solve at 128².
    for (int r = r0; r < r1; ++r) {
      for (int b = 0; b < 4; ++b) {
        const Run u = run_of(f, r, b);
#pragma omp simd
        for (int k = u.k_begin; k < block; ++k) {
          const int i = u.i0 + k;
          const ChainRow c = chain_row(bx, by, bz, mx, my, mz, w, i, u.j0 + k, !fixed[r], rest,
                                       alpha_tilde, gamma);
          sx[i] = c.nx;
          sy[i] = c.ny;
          sz[i] = c.nz;
          sb[i] = c.b;
          sr[i] = c.r;
        }
      }
    }
    // Column t = 4k + b of a group's rows is lane t of slot b·block + k: tile k0 / L of residue
    // b holds columns 4k + b for k in [k0, k0 + L). Lanes of rows past the last read as a
    // constraint that changes nothing (b = 1, all else 0).
    using LaneTiles = typename Lanes<Real>::Tile[4];
    for (int G = g0; G < g1; ++G) {
      const int rows_in = std::min(L, rows_ - G * L);
      for (int k0 = 0; k0 < block; k0 += L) {
        const int cols_in = std::min(L, block - k0);
        LaneTiles tx, ty, tz, tb, tr, tw;
        for (int b = 0; b < 4; ++b) {
          const int s0 = G * L * stride + b * block + k0;
          Lanes<Real>::load(sx + s0, stride, rows_in, cols_in, 0, tx[b]);
          Lanes<Real>::load(sy + s0, stride, rows_in, cols_in, 0, ty[b]);
          Lanes<Real>::load(sz + s0, stride, rows_in, cols_in, 0, tz[b]);
          Lanes<Real>::load(sb + s0, stride, rows_in, cols_in, 1, tb[b]);
          Lanes<Real>::load(sr + s0, stride, rows_in, cols_in, 0, tr[b]);
          Lanes<Real>::load(w + s0, stride, rows_in, cols_in, 0, tw[b]);
        }
        for (int j = 0; j < cols_in; ++j) {
          for (int b = 0; b < 4; ++b) {
            const int t = 4 * (k0 + j) + b, q = G * entries + t + 1;
            if (t + 1 >= cols_) break;
            const ChainRowOf<Lane> c{tx[b][j], ty[b][j], tz[b][j], tb[b][j], tr[b][j]};
            eliminate<Lane>(c, tw[b][j], gamma, alpha_tilde * keep * lambda[q], nx, ny, nz, fe, g,
                            inv_beta, q - 1, q, q);
          }
        }
      }
      for (int k0 = (block - 1) / L * L; k0 >= 0; k0 -= L) {
        const int cols_in = std::min(L, block - k0);
        LaneTiles td;
        for (int j = L - 1; j >= 0; --j) {
          for (int b = 3; b >= 0; --b) {
            const int t = 4 * (k0 + j) + b, q = G * entries + t + 1;
            td[b][j] = t + 1 < cols_ ? substitute<Lane>(g, inv_beta, lambda, keep, omega, q,
                                                        fe[q + 1], g[q + 1])
                                     : Lane{};
          }
        }
        for (int b = 0; b < 4; ++b)
          Lanes<Real>::store(td[b], sdl + G * L * stride + b * block + k0, stride, rows_in,
                             cols_in);
      }
    }
    // The moves, constraint by constraint: a run's constraints share no particle. To the end of
    // each block, as above: the extra constraint's Δλ is 0.
    for (int r = r0; r < r1; ++r) {
      for (int b = 0; b < 4; ++b) {
        const Run u = run_of(f, r, b);
#pragma omp simd
        for (int k = u.k_begin; k < block; ++k) {
          const int i = u.i0 + k, j = u.j0 + k;
          const Real s = omega * sdl[i];
          mx[i] -= w[i] * s * sx[i];
          my[i] -= w[i] * s * sy[i];
          mz[i] -= w[i] * s * sz[i];
          mx[j] += w[j] * s * sx[i];
          my[j] += w[j] * s * sy[i];
          mz[j] += w[j] * s * sz[i];
        }
      }
      if (fixed[r]) sweep_chain(f, h, r * grid_.stride);
    }
  }

  // Sweeps the row whose first slot is `start` spring by spring, kFixedChainSweeps times
  // red–black, each projection from λ = 0.
  void sweep_chain(const Family& f, Real h, int start) {
    const Compliance<Real> compliance_h = compliance(f, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    for (int sweep = 0; sweep < kFixedChainSweeps; ++sweep)
      for (int colour = 0; colour < 2; ++colour)
        for (int t = colour; t + 1 < cols_; t += 2)
          project_fixed_chain(f, alpha_tilde, gamma, start + col_slot_[t],
                              start + col_slot_[t + 1]);
  }

  // The columns through a fixed particle, swept as sweep_chain sweeps a row, each thread the
  // constraints from the rows it solves (the constraints of one colour share no particle, so
  // the bits are those of one thread sweeping each column whole). Swept whole by one thread,
  // every column crossed the other thread's rows, whose cache lines then went back and forth
  // between the cores every pass.
  void sweep_fixed_columns(const Family& f, Real h, int parts) {
    const Compliance<Real> compliance_h = compliance(f, h);
    const Real alpha_tilde = compliance_h.alpha_tilde, gamma = compliance_h.gamma;
    const int stride = grid_.stride;
    for (int sweep = 0; sweep < kFixedChainSweeps; ++sweep) {
      for (int colour = 0; colour < 2; ++colour) {
#pragma omp for schedule(static)
        for (int part = 0; part < parts; ++part) {
          const int r0 = group_row(part_group(part, parts)),
                    r1 = group_row(part_group(part + 1, parts));
          for (int t = r0 + ((r0 ^ colour) & 1); t < std::min(r1, rows_ - 1); t += 2)
            for (int l : fixed_columns_)
              project_fixed_chain(f, alpha_tilde, gamma, t * stride + l, (t + 1) * stride + l);
        }
      }
    }
  }

  // One constraint of a chain through a fixed particle, from λ = 0.
  void project_fixed_chain(const Family& f, Real alpha_tilde, Real gamma, int i, int j) {
    xpbd_project<false, true>(particles_.base.x.data(), particles_.base.y.data(), particles_.base.z.data(), particles_.move.x.data(),
                              particles_.move.y.data(), particles_.move.z.data(), particles_.inv_mass.data(), i, j, Real(f.rest),
                              alpha_tilde, gamma, Real(0));
  }

  // Long-range attachments on every free particle, row by row.
  void apply_attachments() {
#pragma omp for schedule(static)
    for (int r = 0; r < rows_; ++r) attachments_row(r);
  }
  void attachments_row(int r) {
    particles_.attachments(r * grid_.stride, (r + 1) * grid_.stride);
  }

  // Contacts for every free particle, row by row.
  void resolve_contacts(const std::vector<Collider>& colliders) {
#pragma omp for schedule(static)
    for (int r = 0; r < rows_; ++r) contacts_row(colliders, r);
  }
  // The contacts of row r. A run of Particles::contacts holds every fourth column of a stretch
  // of the row (the residue blocks), so it is mostly rows away from a collider that are skipped.
  void contacts_row(const std::vector<Collider>& colliders, int r) {
    particles_.contacts(colliders, r * grid_.stride, (r + 1) * grid_.stride);
  }

  // The layers `held` apart, contacts, then v = move/h; with `triangles`, the triangles
  // against moving bodies between the two, and so the pairs with sharp features where there
  // are `features`.
  void finish_substep(const std::vector<Collider>& colliders, Real h, bool triangles,
                      const FeatureContacts* features, const HeldLayers* held) {
    if (held) {
#pragma omp single
      particles_.held_layers(*held, [&](int32_t i) { return grid_.slot(i); });
    }
    if (triangles || features) {
      resolve_contacts(colliders);
#pragma omp single
      {
        if (triangles) particles_.triangle_contacts(colliders, triangles_);
        if (features)
          particles_.feature_contacts(*features, colliders,
                                      [&](int32_t i) { return grid_.slot(i); });
      }
#pragma omp for schedule(static)
      for (int r = 0; r < rows_; ++r)
        particles_.velocities(h, r * grid_.stride, (r + 1) * grid_.stride);
      return;
    }
#pragma omp for schedule(static)
    for (int r = 0; r < rows_; ++r) {
      contacts_row(colliders, r);
      particles_.velocities(h, r * grid_.stride, (r + 1) * grid_.stride);
    }
  }

  int cols_ = 0, rows_ = 0;
  GridLayout grid_;
  // Whether the arrays below hold the state as the last frame left it, nothing having changed
  // it since (prepare(), state_changed()). The next frame then starts from them rather than
  // reading the state back: at 128×128 that read took 0.05 ms of a 1 ms frame on two threads,
  // its arrays having left the caches during the frame. They hold each position more exactly
  // than the state does (as base + move, whose sum the state holds rounded to double).
  bool stopping_ = false;  ///< the frame stops early (shared by the threads)
  bool current_ = false;
  int substeps_ = 1;
  double frame_dt_ = 0.0;
  int iterations_ = kDefaultIterations;
  int stiff_sweeps_ = 0;
  double stiffest_ = 0.0;  ///< N/m, the stiffest family's stiffness (what stiff sweeps redo)
  Particles<Real> particles_;
  std::vector<Triangle> triangles_;  ///< corners as slots; built when a collider first moves
  std::vector<Vec3> scratch_;  ///< wind forces, AoS as forces.h writes them
  std::vector<Family> families_;
  AlignedVector<Real> lambda_;  ///< per family and first slot; only with iterations > 1
  bool attached_ = false;  ///< long-range attachments are on
  // Line passes (solver.line_passes).
  int line_passes_ = 0;  ///< as asked
  Real relaxation_ = 1;  ///< ω of every pass but the last (solver.line_relaxation)
  bool lines_ = false;   ///< whether they run now (see prepare_lines)
  int row_family_ = -1, col_family_ = -1;  ///< the structural families along rows and columns
  std::vector<int32_t> col_slot_;          ///< slot of column c within a row
  std::vector<unsigned char> row_fixed_, col_fixed_;  ///< chain holds a fixed particle: swept
  ChainScratch<Lane> row_chains_;                     ///< a lane a row (see solve_rows)
  ChainScratch<Real> col_chains_;
  std::vector<int> fixed_columns_;  ///< the slots in a row of the columns col_fixed_ marks
  int twist_ = 0;                   ///< the columns' twist constraint (see eliminate_columns)
  AlignedVector<Real> twist_beta_, twist_g_;  ///< per column: the top half's pivot, right side
  AlignedVector<Real> twist_fe_, twist_fg_;   ///< per column: what the bottom half takes off them
  AlignedVector<Real> twist_dl_;              ///< per column: the twist's Δλ, the bottom's copy
  Soa<Real> rows_n_;                          ///< per slot: its row constraint's direction
  AlignedVector<Real> rows_b_, rows_r_, rows_dl_;  ///< per slot: its diagonal, right side, Δλ
};

}  // namespace

}  // namespace drape::xpbd

namespace drape {

std::unique_ptr<Solver> make_grid_xpbd(Precision precision) {
  if (precision == Precision::f32) return std::make_unique<xpbd::GridXpbd<float>>();
  return std::make_unique<xpbd::GridXpbd<double>>();
}

}  // namespace drape
