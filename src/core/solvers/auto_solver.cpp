// `auto`: the method a user gets who says what they want (the largest structural strain they
// accept, solver.tolerance) rather than how to get it. It steps with xpbd in single precision
// (the fastest method here at every size and shape, its strain resolved to ~1e-6 near the
// origin, far below any tolerance; in double where float cannot resolve the cloth, far from the
// origin or tiny: kSingleShare) and keeps the cheapest effort that holds the tolerance,
// deciding every kWindow frames from the largest structural strain over them: it raises its
// effort a step on a ladder of settings when the strain passes kRaise of the tolerance, and
// lowers it a step after a calm half second below kLower.
//
// The ladder: on a grid where line passes may run (no pin, or the pins' long-range attachments
// on) the bench's configurations, 4 substeps of 2 to 6 passes with 0 to 2 stiff sweeps after
// them, then more substeps; elsewhere (a mesh, whose line passes gain little; a pinned cloth
// without attachments, which auto may not turn on: that would change the physics) substeps
// with two stiff sweeps each, from xpbd's own automatic count.
//
// The strain of a window is its median frame's largest: a gust or a landing stretches the cloth
// for a frame or two, which no effort would shorten, while a method's error is there every
// frame. Two rules keep it from see-sawing and from paying for nothing. A step down that has to
// be taken back within two windows marks the level below as too low (a floor). Two steps up in
// a row that leave the strain where it was (above 90% of the window before; a step taken while
// the strain was rising is not judged) show that the strain is the springs' own stretch, which no
// effort removes (soft springs, point pins without attachments): both are taken back, the level
// becomes a ceiling for kCeilingFrames, and the choice says the tolerance is out of reach.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "drape/error.h"
#include "drape/simulation.h"
#include "largest_coordinate.h"
#include "long_range.h"
#include "parallel.h"
#include "solver.h"
#include "xpbd/xpbd.h"

namespace drape {

namespace {

struct Effort {
  int substeps, line_passes, stiff_sweeps;
};

// Cheapest first: a stiff sweep after the passes costs a fifth of a pass at 256², half at 128²
// (README, Performance).
constexpr Effort kLineLadder[] = {{4, 2, 0}, {4, 2, 1}, {4, 2, 2}, {4, 3, 1}, {4, 3, 2},
                                  {4, 4, 1}, {4, 4, 2}, {4, 5, 2}, {4, 6, 2}, {6, 6, 2},
                                  {9, 6, 2}, {14, 6, 2}, {21, 6, 2}, {32, 6, 2}};
// Where the line ladder starts: what the bench's cheapest passing runs needed. A free cloth
// (drape, 128² and 256²) 4 + 4 lines + 1 sweep; a pinned one, whose attachments carry the load
// (hang-lr), the least, 4 + 2 lines.
constexpr int kLineStartFree = 5;
constexpr int kLineStartPinned = 0;
constexpr int kSubstepLadder[] = {4,   6,   9,   14,  21,  32,   48,   72,  108,
                                  162, 243, 365, 548, 822, 1233, 1850, 2775};
constexpr int kSweepsWithSubsteps = 2;

constexpr double kRaise = 0.8;    // raise when the strain passes this share of the tolerance
constexpr double kLower = 0.4;    // lower after a calm second below this share
constexpr int kWindow = 10;       // frames between decisions
constexpr int kCalmWindows = 6;   // a second at 60 frames a second
constexpr double kHelped = 0.9;   // a raise must bring the strain below this share of before
constexpr double kRising = 1.1;   // ... unless the strain had grown by this factor before it
constexpr int kCeilingFrames = 300;
// Single precision while its rounding of a position, over the shortest structural spring, is
// at most this share of the tolerance (a 4096² cloth of 2 m near the origin: about 0.05).
constexpr double kSingleShare = 0.1;

class AutoSolver final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    def_ = def;
    const ClothModel& m = w.model;
    spring_i_.clear(), spring_j_.clear(), inv_rest_.clear();
    for (const Spring& s : m.springs) {
      if (s.kind != SpringKind::structural) continue;
      spring_i_.push_back(s.i);
      spring_j_.push_back(s.j);
      inv_rest_.push_back(1.0 / s.rest);
    }
    bool pinned = false;
    for (int32_t i = 0; i < m.size() && !pinned; ++i) pinned = w.state.pinned[i] != 0;
    const bool lines = m.grid.present() && (!pinned || w.attachments.active());
    // A new plan when the kind of ladder changes (pins or attachments changed); the level
    // reached is kept through the preparations the hand, pins and settings cause.
    if (!planned_ || lines != lines_) {
      lines_ = lines;
      ladder_.clear();
      if (lines) {
        ladder_.assign(std::begin(kLineLadder), std::end(kLineLadder));
        level_ = pinned ? kLineStartPinned : kLineStartFree;
      } else {
        for (int s : kSubstepLadder) ladder_.push_back({s, 0, kSweepsWithSubsteps});
        // Start where xpbd's own rule (m/h² ≥ k for every spring) puts it, or at the top.
        int start = def.max_substeps;
        try {
          start = xpbd::automatic_substeps(w, def, [](const Spring&) { return true; });
        } catch (const InputError&) {
        }
        level_ = 0;
        while (level_ + 1 < static_cast<int>(ladder_.size()) && ladder_[level_].substeps < start)
          ++level_;
      }
      // Never past solver.max_substeps.
      while (ladder_.size() > 1 && ladder_.back().substeps > def.max_substeps) ladder_.pop_back();
      if (ladder_.back().substeps > def.max_substeps)
        throw InputError("solver.max_substeps",
                         "is " + std::to_string(def.max_substeps) +
                             ", fewer substeps than the auto method's least (" +
                             std::to_string(ladder_.back().substeps) + ")");
      level_ = std::min(level_, static_cast<int>(ladder_.size()) - 1);
      floor_ = 0, calm_ = 0, since_lower_ = kCalmWindows, ceiling_ = -1, ceiling_frames_ = 0;
      balls_level_ = 0;
      unhelpful_ = 0;
      raised_ = false, frame_ = 0, last_window_strain_ = 0.0, window_before_strain_ = 0.0;
      planned_ = true;
    }
    // Single precision where it resolves the cloth: its rounding at the cloth's coordinates
    // (a cloth far from the origin, as in a game's world, or a tiny one) a small share of the
    // strain allowed on its shortest structural spring; double where not.
    const double scale = largest_coordinate(w.state.x);
    double most_inverse_rest = 0.0;
    for (double inverse : inv_rest_) most_inverse_rest = std::max(most_inverse_rest, inverse);
    const double rounding = std::numeric_limits<float>::epsilon() * scale * most_inverse_rest;
    const Precision precision =
        rounding <= kSingleShare * def.tolerance ? Precision::f32 : Precision::f64;
    if (!inner_ || precision != precision_) {
      precision_ = precision;
      inner_ = m.grid.present() ? make_grid_xpbd(precision_) : make_mesh_xpbd(precision_);
    }
    apply(w);
  }

  void step_frame(World& w, double dt) override {
    hold_off_still_balls(w, dt);
    inner_->step_frame(w, dt);
    if (w.cut_short) return;  // a part of a frame says nothing about the effort it needs
    choice_.strain = max_strain(w.state.x);
    window_[frame_ % kWindow] = choice_.strain;
    if (ceiling_frames_ > 0 && --ceiling_frames_ == 0) ceiling_ = -1;
    if (++frame_ % kWindow == 0) {
      // The window's median frame: the error a method leaves is there in every frame, while a
      // gust or a snap stretches the cloth for a frame or two, which no effort would shorten.
      std::array<double, kWindow> sorted = window_;
      std::nth_element(sorted.begin(), sorted.begin() + kWindow / 2, sorted.end());
      const double strain = sorted[kWindow / 2];
      decide(w, strain);
      window_before_strain_ = last_window_strain_;
      last_window_strain_ = strain;
    }
  }

  void state_changed() override { inner_->state_changed(); }
  bool holds_layers() const override { return inner_->holds_layers(); }
  int substeps() const override { return inner_->substeps(); }
  int64_t workspace_bytes() const override {
    return inner_->workspace_bytes() + heap_bytes(spring_i_, spring_j_, inv_rest_, ladder_);
  }
  const AutoChoice* auto_choice() const override { return &choice_; }

 private:
  // One decision on the strain of the window just ended.
  void decide(const World& w, double strain) {
    const double tolerance = def_.tolerance;
    const int top = ceiling_ >= 0 ? ceiling_ : static_cast<int>(ladder_.size()) - 1;
    ++since_lower_;
    if (strain <= tolerance) choice_.out_of_reach = false;
    if (strain > kRaise * tolerance) {
      calm_ = 0;
      // A step up taken while the strain was rising (the cloth falling, landing, swinging out)
      // cannot be judged by the window after it.
      if (raised_ && last_window_strain_ <= kRising * window_before_strain_)
        unhelpful_ = strain > kHelped * last_window_strain_ ? unhelpful_ + 1 : 0;
      if (unhelpful_ >= 2) {
        // Two steps up in a row did not help: take both back and go no higher for a while.
        const int back = std::max(0, level_ - 2);
        ceiling_ = back;
        ceiling_frames_ = kCeilingFrames;
        choice_.out_of_reach = strain > tolerance;
        raised_ = false;
        unhelpful_ = 0;
        change(w, back);
        ++choice_.lowers;
        return;
      }
      raised_ = false;
      if (level_ < top) {
        if (since_lower_ <= 2) floor_ = std::max(floor_, level_ + 1);
        change(w, level_ + 1);
        raised_ = true;
        ++choice_.raises;
      }
      return;
    }
    raised_ = false;
    unhelpful_ = 0;
    if (strain < kLower * tolerance) {
      if (++calm_ >= kCalmWindows && level_ > floor_) {
        calm_ = 0;
        since_lower_ = 0;
        change(w, level_ - 1);
        ++choice_.lowers;
      }
    } else {
      calm_ = 0;
    }
  }

  void change(const World& w, int level) {
    level_ = level;
    apply(w);
  }

  // Cloth coming fast at a small still ball parts round it at few substeps, and the strain does
  // not show it (a sheet dropped onto a ball of radius 10 cm at 10 m/s: xpbd with 2 line passes
  // let it through at 4 and 6 substeps a frame, held at 9 and more). The frames where that can
  // happen step at least at the level whose substeps keep the ball's move relative to the
  // cloth near it within a sixteenth of its radius (ColliderSet::substeps_for, as `implicit`);
  // the strain's level_ is kept for after. Moving bodies do not count: xpbd keeps the cloth's
  // triangles out of those.
  void hold_off_still_balls(const World& w, double dt) {
    int level = 0;
    if (w.bodies) {
      const int needed = w.bodies->substeps_for(w.state.x, w.state.v, w.state.inv_mass, w.time,
                                                w.time + dt, ColliderSet::Counted::still_round);
      while (level + 1 < static_cast<int>(ladder_.size()) && ladder_[level].substeps < needed)
        ++level;
    }
    if (level == balls_level_) return;
    balls_level_ = level;
    if (std::max(level_, balls_level_) != applied_) apply(w);
  }

  // Prepares xpbd with the ladder's settings at level_, or higher where still balls ask for it.
  void apply(const World& w) {
    applied_ = std::max(level_, balls_level_);
    const Effort& e = ladder_[applied_];
    SolverDef d = def_;
    d.method = Method::xpbd;
    d.precision = precision_;
    d.substeps = e.substeps;
    d.line_passes = e.line_passes;
    d.stiff_sweeps = e.stiff_sweeps;
    inner_->prepare(w, d);
    choice_.method = Method::xpbd;
    choice_.precision = precision_;
    choice_.substeps = e.substeps;
    choice_.line_passes = e.line_passes;
    choice_.stiff_sweeps = e.stiff_sweeps;
  }

  // The largest structural strain |length/rest − 1|: a maximum, the same for any thread count.
  double max_strain(const std::vector<Vec3>& x) const {
    const int64_t n = static_cast<int64_t>(spring_i_.size());
    double worst = 0.0;
#pragma omp parallel for schedule(static) reduction(max : worst) if (worth_threads(n))
    for (int64_t k = 0; k < n; ++k)
      worst = std::max(worst,
                       std::abs((x[spring_j_[k]] - x[spring_i_[k]]).norm() * inv_rest_[k] - 1.0));
    return worst;
  }

  SolverDef def_;
  std::unique_ptr<Solver> inner_;
  Precision precision_ = Precision::f32;      ///< inner_'s
  std::vector<int32_t> spring_i_, spring_j_;  ///< the structural springs, whose strain is held
  std::vector<double> inv_rest_;
  bool planned_ = false, lines_ = false;
  std::vector<Effort> ladder_;
  int level_ = 0, floor_ = 0, calm_ = 0;
  int balls_level_ = 0;  ///< the least level still balls ask for this frame
  int applied_ = 0;      ///< the level xpbd was last prepared at: max(level_, balls_level_)
  int since_lower_ = 0;                 ///< windows since the last step down
  int ceiling_ = -1, ceiling_frames_ = 0;  ///< no higher than ceiling_ for that many frames
  bool raised_ = false;                 ///< the last window ended with a step up
  int unhelpful_ = 0;                   ///< steps up in a row that left the strain as it was
  int64_t frame_ = 0;
  std::array<double, kWindow> window_{};  ///< the largest strain of each frame of the window
  double last_window_strain_ = 0.0, window_before_strain_ = 0.0;
  AutoChoice choice_;
};

// A material's cloth: its strain is the fabric's own stretch, not an error any effort removes,
// and its threads buckle, which the line passes' inextensible chains cannot. auto takes xpbd
// (double precision, its automatic substeps) where those are few, implicit where many, chosen
// at the first preparation and kept, from what each costs on the material scenes (README,
// Materials): xpbd about 0.12 µs per particle and substep; implicit, at one step a frame, 6 to
// 8 µs per particle and frame on a stiff fabric hanging free (50 to 67 substeps' worth) and 14
// to 25 µs on one landing on a collider, where it takes more steps (sphere-denim: 115 to 200
// substeps' worth). So xpbd up to kMaterialXpbdSubstepsFree substeps without colliders
// (hang-denim in knit, 17, a tie; implicit for it in denim, 74, and in cotton-polyester, 128:
// 1.4 and 2.3 times faster), up to kMaterialXpbdSubstepsColliding with them (xpbd for the
// draping sphere-denim, 50 to 114 substeps by preset: 1.7 to 2 times faster; implicit for the
// fine disc of cusick, 273: 6 to 8 times). The choice is reported as auto's (AutoChoice).
constexpr int kMaterialXpbdSubstepsFree = 60;
constexpr int kMaterialXpbdSubstepsColliding = 150;

class MaterialAuto final : public Solver {
 public:
  void prepare(const World& w, const SolverDef& def) override {
    SolverDef d = def;
    d.precision = Precision::f64;
    if (!inner_) {
      d.method = Method::xpbd;
      const int most =
          w.colliders.empty() ? kMaterialXpbdSubstepsFree : kMaterialXpbdSubstepsColliding;
      int needed = most + 1;
      try {
        needed = xpbd::automatic_substeps(w, d, [](const Spring&) { return true; });
      } catch (const InputError&) {  // more than solver.max_substeps: implicit
      }
      if (needed > most) d.method = Method::implicit;
      inner_ = make_solver(d, w.model);
      choice_.method = d.method;
      choice_.precision = d.precision;
    }
    d.method = choice_.method;
    inner_->prepare(w, d);
    choice_.substeps = inner_->substeps();
  }
  void step_frame(World& w, double dt) override { inner_->step_frame(w, dt); }
  void state_changed() override { inner_->state_changed(); }
  int substeps() const override { return inner_->substeps(); }
  int64_t workspace_bytes() const override { return inner_->workspace_bytes(); }
  bool stretch_is_energy() const override { return inner_->stretch_is_energy(); }
  bool may_tear() const override { return inner_->may_tear(); }
  bool steps_any_dt() const override { return inner_->steps_any_dt(); }
  bool holds_layers() const override { return inner_->holds_layers(); }
  const AutoChoice* auto_choice() const override { return &choice_; }

 private:
  std::unique_ptr<Solver> inner_;
  AutoChoice choice_;
};

}  // namespace

std::unique_ptr<Solver> make_auto() { return std::make_unique<AutoSolver>(); }
std::unique_ptr<Solver> make_material_auto() { return std::make_unique<MaterialAuto>(); }

}  // namespace drape
