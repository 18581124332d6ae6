#include "drape/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "collision/collider_set.h"
#include "collision/motion.h"
#include "collision/self_collision.h"
#include "drape/error.h"
#include "forces.h"
#include "forces/bending.h"
#include "largest_coordinate.h"
#include "long_range.h"
#include "solvers/solver.h"
#include "solvers/system_factor.h"

namespace drape {

namespace {

// A cloth that starts inside a collider is thrown out of it by the first contact pass, with
// energy that nothing supplied, and the divergence watch would report a blow-up and a hint
// about the step: it is the scene that is wrong. A particle inside by no more than the
// collider's thickness and the cloth's perturbation is the cloth laid on the surface; contacts
// move it out by that much.
void check_starts_outside(const std::vector<Collider>& colliders, double perturbation,
                          const std::vector<Vec3>& x) {
  for (size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k];
    const double allowed = c.thickness + perturbation + 1e-9;
    int64_t inside = 0;
    double depth = 0.0;
    Vec3 deepest = Vec3::Zero(), n;
    for (const Vec3& p : x) {
      const double d = -signed_distance(c, p, n);
      if (d <= allowed) continue;
      ++inside;
      if (d > depth) depth = d, deepest = p;
    }
    if (inside == 0) continue;
    const bool plane = c.type == ColliderType::plane;
    char problem[320];
    std::snprintf(problem, sizeof problem,
                  "the cloth starts %s this %s: %lld of its %zu particles do, the deepest (at "
                  "%.3g, %.3g, %.3g) %.3g m %s; move the cloth or the %s%s",
                  plane ? "behind" : "inside", to_string(c.type), static_cast<long long>(inside),
                  x.size(), deepest.x(), deepest.y(), deepest.z(), depth,
                  plane ? "behind it" : "inside its surface", to_string(c.type),
                  plane ? ", or turn its normal to the cloth's side" : "");
    throw InputError("colliders[" + std::to_string(k) + "]", problem);
  }
}

// The rest length of the model's shortest spring (infinity for none).
double shortest_spring(const ClothModel& m) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const Spring& s : m.springs) shortest = std::min(shortest, s.rest);
  return shortest;
}

// A moving pin carries its particles, and the cloth hanging from them, as far as its keys'
// translations and its turn about its pivot reach: at most |pivot| + the farthest particle
// from the pivot + the longest translation (the translation between two keys is a blend of
// theirs, the turn keeps distances to the pivot). A pin moved 1e20 m ran on with strains of
// 1e23% and exited 0. The cloth must stay within `limit` m of the origin (check_resolvable),
// which its shortest spring, `shortest` m at rest, sets.
void check_pins_resolvable(const ClothDef& def, const ClothModel& m, double shortest,
                           double limit) {
  for (size_t k = 0; k < def.pins.size(); ++k) {
    const MotionDef& motion = def.pins[k].motion;
    if (!motion.moves()) continue;
    const std::vector<int32_t> particles = pin_particles(def, m, k);
    if (particles.empty()) continue;
    Vec3 centre = Vec3::Zero();
    for (const int32_t i : particles)
      centre += m.rest_position[i] / static_cast<double>(particles.size());
    const Vec3 pivot = motion.has_pivot ? motion.pivot : centre;
    double turned = 0.0, moved = 0.0;
    for (const int32_t i : particles)
      turned = std::max(turned, (m.rest_position[i] - pivot).norm());
    for (const MotionKey& key : motion.keys) moved = std::max(moved, key.translate.norm());
    const double farthest = pivot.norm() + turned + moved;
    if (farthest <= limit) continue;
    char problem[320];
    std::snprintf(problem, sizeof problem,
                  "carries its particles up to %.3g m from the origin, where positions are "
                  "rounded in steps of %.3g m: too coarse for the cloth's shortest spring, %.3g "
                  "m at rest; keep the pinned particles within %.3g m of the origin",
                  farthest, farthest * std::numeric_limits<double>::epsilon(), shortest, limit);
    throw InputError("cloth.pins[" + std::to_string(k) + "].motion", problem);
  }
}

// Coordinates so large that double precision cannot hold the cloth's edges: a grid placed
// 1e20 m from the origin had its particles rounded onto each other, ran with springs of rest
// length 0 (its strain printed as "inf%") and exited 0; at 1e307 it "diverged" with a hint
// about the step. Every spring must span at least 2^10 steps of its ends' rounding, so that
// positions hold it to about a thousandth, under the strains a user is shown and the bars held
// (1e-2): a cloth of 1 cm edges may lie 4e10 m from the origin.
void check_resolvable(const ClothDef& def, const ClothModel& m) {
  constexpr double kStepsPerEdge = 0x1p10;
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  // `shortest`: the model's shortest_spring, measured once per model.
  auto resolvable = [&](const ClothModel& model, double shortest) {
    return model.springs.empty() ||
           shortest >= kStepsPerEdge * kEpsilon * largest_coordinate(model.rest_position);
  };
  const double shortest = shortest_spring(m);
  if (resolvable(m, shortest)) {
    check_pins_resolvable(def, m, shortest, shortest / (kStepsPerEdge * kEpsilon));
    return;
  }
  // The cloth built where its placing (the grid's origin, the mesh's translation) does not put
  // it: if it is held there, the placing is at fault, and the springs it has there say how far
  // it may go; else the mesh's own vertices are.
  ClothDef here = def;
  here.origin = Vec3::Zero();
  here.transform.translate = Vec3::Zero();
  const ClothModel unplaced = build_model(here);
  const double meant = shortest_spring(unplaced);
  const bool placed = resolvable(unplaced, meant);
  const double largest = largest_coordinate(m.rest_position);
  const std::string key = !placed    ? cloth_mesh_key(def)
                          : def.mesh ? "cloth.transform"
                                     : "cloth.origin";
  char problem[400];
  std::snprintf(problem, sizeof problem,
                "%s up to %.3g m from the origin, where positions are rounded in steps of %.3g "
                "m: too coarse for its shortest spring, %.3g m at rest, which needs steps of a "
                "thousandth of it; ",
                placed ? "places the cloth" : "has vertices", largest, largest * kEpsilon, meant);
  std::string advice = "move its vertices nearer the origin";
  if (placed) {
    char within[96];
    std::snprintf(within, sizeof within, "keep the cloth within %.3g m of the origin",
                  meant / (kStepsPerEdge * kEpsilon));
    advice = within;
  }
  throw InputError(key, problem + advice);
}

}  // namespace

Simulation::Simulation(const SceneDef& def)
    : def_(def), attachments_(std::make_unique<LongRange>()) {
  check(def_);
  model_ = build_model(def_.cloth);
  check_resolvable(def_.cloth, model_);
  state_ = initial_state(def_.cloth, model_);
  Vec3 lo = model_.rest_position[0], hi = lo;
  for (const Vec3& x : model_.rest_position) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  diagonal_ = (hi - lo).norm();
  for (const double m : model_.mass) total_mass_ += m;
  colliders_ = std::make_unique<ColliderSet>(def_.colliders, 0.0);
  // The perturbation moved the start by up to this much (cloth.perturbation is relative).
  check_starts_outside(colliders_->now(), def_.cloth.perturbation * model_.mean_edge, state_.x);
  solver_ = make_solver(def_.solver, model_);
  scratch_.reserve(model_.size());
  for (size_t k = 0; k < def_.cloth.pins.size(); ++k) {
    PinEntry e;
    e.particles = pin_particles(def_.cloth, model_, k);
    for (const int32_t i : e.particles) {
      e.start.push_back(state_.x[i]);
      e.centre += state_.x[i] / static_cast<double>(e.particles.size());
    }
    pin_entries_.push_back(std::move(e));
    pins_move_ = pins_move_ || def_.cloth.pins[k].motion.moves();
  }
  move_pins(0.0, def_.solver.dt);  // where the motions have them at the start
  for (int32_t i = 0; i < model_.size(); ++i) state_.v[i] = Vec3::Zero();
  attachments_->prepare(model_, state_, def_.cloth.long_range);
  prepare_self_collision();
  prepare_features();
  prepare_solver();
  rebase_energy();
}

Simulation::~Simulation() = default;

bool Simulation::move_pins(double t, double dt) {
  if (!pins_move_) return false;
  for (size_t k = 0; k < pin_entries_.size(); ++k) {
    const MotionDef& motion = def_.cloth.pins[k].motion;
    if (!motion.moves()) continue;
    const PinEntry& e = pin_entries_[k];
    const Pose pose = pose_at(motion, e.centre, t);
    for (size_t j = 0; j < e.particles.size(); ++j) {
      const int32_t i = e.particles[j];
      if (!state_.pinned[i] || i == grabbed_) continue;  // unpinned in the viewer, or held
      const Vec3 x = pose.apply(e.start[j]);
      state_.v[i] = (x - state_.x[i]) / dt;
      state_.x[i] = state_.anchor[i] = x;
    }
  }
  return true;
}
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::prepare_self_collision() {
  const SelfCollisionDef& sc = def_.cloth.self_collision;
  if (!sc.enabled) {
    self_collision_.reset();
    return;
  }
  // Thicker than half an edge, the layers' gap would reach across the cloth's own triangles:
  // neighbours in one flat layer would push each other apart.
  const double limit = 0.5 * model_.mean_edge;
  if (sc.thickness > limit) {
    char problem[240];
    std::snprintf(problem, sizeof problem,
                  "is %.3g m, more than half the cloth's mean edge length (%.3g m) allows; give "
                  "at most %.3g m, or 0 for the automatic quarter edge (%.3g m)",
                  sc.thickness, model_.mean_edge, limit, 0.5 * limit);
    throw InputError("cloth.self_collision.thickness", problem);
  }
  if (!self_collision_) self_collision_ = std::make_unique<SelfCollision>();
  self_collision_->prepare(model_, self_collision_thickness(sc, model_), sc.friction);
}

void Simulation::prepare_features() {
  const auto& now = colliders_->now();
  if (std::none_of(now.begin(), now.end(),
                   [](const Collider& c) { return c.features != nullptr; })) {
    features_.reset();
    return;
  }
  features_ = std::make_unique<FeatureContacts>();
  features_->prepare(model_);
  travel_.assign(now.size(), 0.0);
}

void Simulation::solve(World& world, double dt) {
  world.features = nullptr;
  if (features_) {
    for (size_t k = 0; k < travel_.size(); ++k)
      travel_[k] = colliders_->travel(k, world.time, world.time + dt);
    features_->gather(colliders_->now(), travel_, state_, def_.forces.gravity, dt);
    if (features_->any()) world.features = features_.get();
  }
  solver_->step_frame(world, dt);
  if (features_) features_->check(state_.x);
}

const SelfCollisionReport* Simulation::self_collision() const {
  return self_collision_ ? &self_collision_->report() : nullptr;
}

int Simulation::substeps_per_frame() const {
  return solver_->substeps();
}
const AutoChoice* Simulation::auto_choice() const {
  return solver_->auto_choice();
}

const std::vector<Collider>& Simulation::colliders() const {
  return colliders_->now();
}

void Simulation::prepare_solver() {
  World world{model_, state_, def_.forces, colliders_->contact(), time(), *attachments_};
  solver_->prepare(world, def_.solver);
}

double Simulation::mechanical_energy() const {
  return forces::kinetic_energy(model_, state_.v) +
         forces::gravity_energy(model_, state_.x, def_.forces.gravity) +
         forces::spring_energy(model_, state_.x) + forces::bending_energy(model_, state_.x);
}

void Simulation::rebase_energy() {
  energy_ref_ = mechanical_energy();
  external_work_ = 0.0;
}

namespace {

// A spring longer than this × its rest length is torn, not stretched by a solver's inaccuracy
// (`implicit`'s one Newton step leaves the bench's stiff drape at most 9% long; a torn jittered
// mesh passed 100% within 15 frames and went on to 5000%: README, Known traps).
constexpr double kTornStretch = 2.0;

// What to try when a method blows up.
const char* divergence_hint(Method m) {
  switch (m) {
    case Method::symplectic:
      return "try a smaller solver.dt, more solver.substeps (0 = automatic), lower stiffness, or "
             "the implicit method";
    case Method::implicit:
      return "try a smaller solver.dt, more solver.substeps, a smaller solver.cg_tolerance or "
             "more solver.cg_max_iterations";
    case Method::xpbd:
      return "try more solver.substeps or solver.iterations, or a smaller solver.dt";
    case Method::fast:
      return "try more solver.iterations, more solver.substeps, or the implicit method";
    case Method::automatic:
      return "try a smaller solver.dt or a larger solver.max_substeps";
  }
  return "";
}

}  // namespace

void Simulation::step_with_self_collision(World& world) {
  // The collision stage keeps layers apart when they move less than a few thicknesses relative
  // to each other between two of its passes; a frame in which layers in contact moved past
  // each other faster (a cloth crumpling on landing) is split into parts, each solved and then
  // collision-checked. The parts are chosen from the last frame's contacts, so a resting pile,
  // or a cloth that touches nothing of itself however it moves, costs one pass.
  const double dt = def_.solver.dt;
  // (fast's matrix is factorised for the whole frame: it takes one part.)
  const int parts = solver_->steps_any_dt() ? self_collision_->parts_for(frame_motion_) : 1;
  for (int part = 0; part < parts && !world.cut_short; ++part) {
    if (move_pins(time() + dt * (part + 1) / parts, dt / parts)) solver_->state_changed();
    frame_start_ = state_.x;
    world.time = time() + dt * part / parts;
    world.held = nullptr;
    if (solver_->holds_layers()) {
      const HeldLayers& held = self_collision_->hold_layers(model_, state_, colliders_->contact());
      if (held.any()) world.held = &held;
    }
    solve(world, dt / parts);
    // Even a part cut short is checked: the next frame starts from it.
    if (self_collision_->resolve(model_, frame_start_, colliders_->contact(), dt / parts, state_,
                                 solver_->holds_layers()))
      solver_->state_changed();
    if (part == 0) frame_motion_ = self_collision_->near_motion() * parts;
  }
}

bool Simulation::step() {
  if (diverged()) return false;
  World world{model_, state_, def_.forces, colliders_->contact(), time(), *attachments_, stop_};
  world.bodies = colliders_.get();
  if (colliders_->moves()) world.moving = colliders_.get();
  if (self_collision_) {
    step_with_self_collision(world);
  } else {
    // Moving pins are placed where they are at the frame's end, before it (the solvers hold
    // pins still through a frame).
    if (move_pins(time() + def_.solver.dt, def_.solver.dt)) solver_->state_changed();
    solve(world, def_.solver.dt);
  }
  stopped_ = world.cut_short;
  if (stopped_) return true;  // part of a frame: not counted, and its energy is not watched
  ++frame_;
  // A sweep that needed more poses than it may take, with cloth in its path: the body may have
  // jumped the cloth, which the promise that nothing tunnels forbids. Said, not passed over.
  if (colliders_->moves()) {
    const ColliderSet::Outrun out =
        colliders_->outrun(state_.x, state_.v, model_.triangles, def_.solver.dt);
    if (out.collider >= 0) {
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "colliders[%d] moved %.3g m in one substep, farther than its sweep's %d "
                    "poses cover (%.3g m), with cloth in its path: it may have passed through "
                    "the cloth; slow its motion, or take %s",
                    out.collider, out.travel, ColliderSet::kMaxSweep, out.covered,
                    def_.solver.method == Method::automatic
                        ? "a smaller solver.dt"
                        : "more solver.substeps or a smaller solver.dt");
      divergence_ = buf;
      diverged_frame_ = frame_;
      return false;
    }
  }
  // A moving collider does work on the cloth that the watch below cannot count: while one
  // moves, its budget starts again from every frame's state (as while the hand holds a
  // particle), so only a blow-up within one frame is caught then.
  const bool pushed = colliders_->settle(time());

  // Divergence watch. The energy now may not exceed what the start state (kinetic, spring and
  // gravity energy at the last rebase), gravity's work since and the wind's work (bounded by
  // Σ|f·v| over each frame) can supply; the reference is rebased while the user's hand holds a
  // particle. For the iterative methods the springs' present energy is not counted, only the
  // kinetic: stopping short of convergence leaves springs stretched, which is inaccuracy, not a
  // blow-up (Solver::stretch_is_energy); only springs past kTornStretch × their rest length,
  // torn, count for a method whose linearised step can tear the cloth without its kinetic
  // energy showing it (Solver::may_tear). A blow-up grows exponentially, so a tolerance of
  // ½·M·(1 m/s)² + M·|g|·(cloth diagonal), far above any stable run's error, catches it within a
  // frame.
  //
  // Finiteness and the two energies are taken in one pass over the state, in parallel: taken
  // one after the other on one thread, they were 0.05 ms of a 0.84 ms frame (hang-lr 128×128 on
  // two threads), which no number of threads shortened.
  const forces::StateWatch watch = forces::watch_state(model_, state_, def_.forces.gravity);
  // Written only on divergence: a frame that goes well allocates nothing here.
  auto method = [&](const char* hint = nullptr) {
    return std::string(" with the ") + to_string(def_.solver.method) + " method; " +
           (hint ? hint : divergence_hint(def_.solver.method));
  };
  if (!watch.finite) {
    divergence_ =
        "the state became non-finite or overflowed (NaN, infinity, or a position or velocity "
        "beyond 1e150)" +
        method();
  } else {
    if (def_.forces.wind.strength > 0.0)
      external_work_ +=
          def_.solver.dt * forces::wind_power(model_, state_, def_.forces.wind, time(), scratch_);
    if (grabbed_ >= 0 || pushed || pins_move_) rebase_energy();  // work the hand or the body did
    const double mass = def_.cloth.material ? total_mass_ : def_.cloth.mass;
    const double tolerance = 0.5 * mass + mass * def_.forces.gravity.norm() * diagonal_;
    double energy = watch.kinetic, torn = 0.0;
    if (solver_->stretch_is_energy())
      energy += forces::spring_energy(model_, state_.x) + forces::bending_energy(model_, state_.x);
    else if (solver_->may_tear())
      energy += torn = forces::spring_energy_beyond(model_, state_.x, kTornStretch);
    const double supplied = energy_ref_ + external_work_ - watch.gravity;
    // An energy that overflowed compares false with anything; so does an excess of inf − inf.
    if (!std::isfinite(energy) || !std::isfinite(supplied)) {
      divergence_ = "the energy overflowed (it is no longer a finite number)" + method();
    } else if (energy - supplied > tolerance) {
      // The excess, not the budget: a budget can be negative (the cloth risen far above where
      // anything could have lifted it), and "more than −7.7e+06 J" reads as nonsense.
      char buf[300];
      if (torn > 0.0)
        std::snprintf(buf, sizeof buf,
                      "the cloth is being torn apart: springs stretched past %g times their rest "
                      "length hold %.3g J, and the energy, %.3g J, is %.3g J more than gravity, "
                      "wind and the start state can supply (tolerance %.3g J)",
                      kTornStretch, torn, energy, energy - supplied, tolerance);
      else
        std::snprintf(buf, sizeof buf,
                      "the energy grew to %.3g J, %.3g J more than gravity, wind and the start "
                      "state can supply (tolerance %.3g J)",
                      energy, energy - supplied, tolerance);
      // Torn by implicit's step: CG's settings do not mend it (the bench's jittered mesh tore
      // as far with cg_tolerance 1e-8), shorter steps do (4 a frame held it). Under the seed's
      // drag per particle, which implicit takes after its solve, the light particles it holds
      // back can tear the cloth at any number of steps (a mesh that slid off a sheet tore at 8
      // a frame; README, Known traps): then less drag mends it too.
      const bool step_tore = torn > 0.0 && def_.solver.method == Method::implicit;
      const bool dragged = def_.forces.air_drag_for(def_.cloth.material.has_value()) > 0.0;
      divergence_ =
          buf + method(!step_tore ? nullptr
                       : dragged
                           ? "it takes forces.air_drag (the drag per particle) after its "
                             "solve, and the light particles it holds back can pull the cloth "
                             "apart: try the xpbd or fast method, less forces.air_drag, or more "
                             "solver.substeps or a smaller solver.dt"
                           : "try more solver.substeps or a smaller solver.dt, or the xpbd or "
                             "fast method");
    }
  }
  if (diverged()) diverged_frame_ = frame_;
  return !diverged();
}

int64_t particle_count(const ClothDef& def) {
  return def.mesh ? static_cast<int64_t>(def.mesh->positions.size()) : int64_t{def.cols} * def.rows;
}

int64_t estimated_memory(const SceneDef& def) {
  const int64_t n = particle_count(def.cloth);
  // Measured per particle (memory() at 64×64 and 256×256): state 113 B, model 333–338 B;
  // workspace symplectic 32 B, xpbd 136 B (84 B single; with line passes 297 B, 164 B
  // single), implicit 781–789 B, fast 1036 B at 4096 particles rising to 1508 B at 65 536
  // (about 118 B per doubling).
  int64_t workspace = 0, factor = 0;
  switch (def.solver.method) {
    case Method::symplectic:
      workspace = 64;
      break;
    case Method::xpbd:
      workspace = def.solver.line_passes > 0 ? 384 : 192;
      break;
    case Method::automatic:
      // xpbd's with line passes and its springs; with a material, implicit's (its largest).
      workspace = def.cloth.material ? 1024 : 384 + 24;
      if (def.cloth.material) factor = SystemFactor::estimated_bytes(n);
      break;
    case Method::implicit:  // and the factor it may make where block-Jacobi CG is slow
      workspace = 1024;
      factor = SystemFactor::estimated_bytes(n);
      break;
    case Method::fast:
      workspace = std::max<int64_t>(1024, 128 * static_cast<int64_t>(std::log2(double(n) + 1)));
      break;
  }
  // Long-range attachments: up to LongRange::kMaxTethers pins and limits per particle.
  if (def.cloth.long_range.enabled) workspace += 48;
  // Self-collision: its boxes, grids, smooth patches and crossing search, and the contacts
  // found, which grow as a cloth piles up (measured 1,700 to 2,330 B per particle on
  // pile.json at 32², 64² and 128² over 5 s).
  if (def.cloth.self_collision.enabled) workspace += 3072;
  return n * (512 + workspace) + factor;
}

MemoryUse Simulation::memory() const {
  MemoryUse m;
  m.state = heap_bytes(state_);
  m.model = heap_bytes(model_);
  m.workspace = solver_->workspace_bytes() + heap_bytes(scratch_, frame_start_) +
                colliders_->bytes() + attachments_->bytes() +
                (self_collision_ ? self_collision_->bytes() : 0) +
                (features_ ? features_->bytes() : 0);
  return m;
}

Diagnostics Simulation::diagnostics() const {
  Diagnostics d;
  d.kinetic_energy = forces::kinetic_energy(model_, state_.v);
  std::vector<double> strains;
  strains.reserve(model_.springs.size() / 2);
  double strain_sum = 0.0;
  for (const Spring& s : model_.springs) {
    if (s.kind != SpringKind::structural) continue;
    const double strain = std::abs((state_.x[s.j] - state_.x[s.i]).norm() / s.rest - 1.0);
    d.max_strain = std::max(d.max_strain, strain);
    strain_sum += strain;
    strains.push_back(strain);
  }
  if (!strains.empty()) {
    d.mean_strain = strain_sum / static_cast<double>(strains.size());
    const size_t k = std::min(strains.size() - 1, static_cast<size_t>(0.99 * strains.size()));
    std::nth_element(strains.begin(), strains.begin() + k, strains.end());
    d.p99_strain = strains[k];
  }
  d.max_penetration = max_penetration(colliders_->now(), state_.x);
  for (int32_t i = 0; i < model_.size(); ++i) {
    if (state_.pinned[i])
      d.pinned_drift = std::max(d.pinned_drift, (state_.x[i] - state_.anchor[i]).norm());
    d.finite = d.finite && state_.x[i].allFinite() && state_.v[i].allFinite();
  }
  // Maxima skip NaN (every comparison with it is false), so a state holding NaN would report
  // figures of its other particles, or 0: its figures from positions are NaN instead.
  if (!d.finite) {
    for (double* figure :
         {&d.max_strain, &d.mean_strain, &d.p99_strain, &d.max_penetration, &d.pinned_drift})
      if (std::isfinite(*figure)) *figure = std::numeric_limits<double>::quiet_NaN();
  }
  // A figure that overflowed is as much a sign of a blown-up state as a position that did.
  for (const double figure : {d.kinetic_energy, d.max_strain, d.mean_strain, d.p99_strain,
                              d.max_penetration, d.pinned_drift})
    d.finite = d.finite && std::isfinite(figure);
  return d;
}

bool Simulation::reconfigure(const SceneDef& def) {
  check(def);
  const ClothDef &a = def_.cloth, &b = def.cloth;
  auto same_pin = [](const Pin& p, const Pin& q) {
    return p.kind == q.kind && p.col == q.col && p.row == q.row && p.vertex == q.vertex &&
           p.box_min == q.box_min && p.box_max == q.box_max;
  };
  const bool same_pins = a.pins.size() == b.pins.size() &&
                         std::equal(a.pins.begin(), a.pins.end(), b.pins.begin(), same_pin);
  const bool same_transform = a.transform.translate == b.transform.translate &&
                              a.transform.rotate == b.transform.rotate &&
                              a.transform.scale == b.transform.scale;
  if (a.cols != b.cols || a.rows != b.rows || a.width != b.width || a.height != b.height ||
      a.origin != b.origin || a.orientation != b.orientation || a.perturbation != b.perturbation ||
      a.mesh != b.mesh || !same_transform || !same_pins)
    return false;
  // A material's masses, springs and bending elements are cooked from it and the mesh: a
  // changed material (or a change to or from one) is a new cloth.
  auto same_material = [](const std::optional<MaterialDef>& p, const std::optional<MaterialDef>& q) {
    if (!p || !q) return !p && !q;
    return p->density == q->density && p->stretch == q->stretch && p->shear == q->shear &&
           p->bending == q->bending && p->compression == q->compression &&
           p->damping == q->damping;
  };
  if (!same_material(a.material, b.material)) return false;

  // Build the new solver first so a refused set-up leaves the simulation as it was.
  SceneDef old = def_;
  def_ = def;
  for (Spring& s : model_.springs) {
    if (b.material) break;  // the material's own, unchanged
    const SpringParams& p = s.kind == SpringKind::structural ? b.structural
                            : s.kind == SpringKind::shear    ? b.shear
                                                             : b.bending;
    s.stiffness = p.stiffness;
    s.damping = p.damping;
  }
  // Masses: the grid's equal shares exactly, a mesh's by area (scaled to the new total).
  for (int32_t i = 0; i < model_.size() && !b.material; ++i) {
    const double m =
        model_.grid.present() ? b.mass / model_.size() : model_.mass[i] * (b.mass / a.mass);
    if (i == grabbed_) grabbed_inv_mass_ = 1.0 / m;
    model_.mass[i] = m;
    if (state_.inv_mass[i] != 0.0) state_.inv_mass[i] = 1.0 / m;
  }
  // The hand's offsets stay with the colliders that are still there (a panel change does not
  // send a dragged ball back).
  auto colliders = std::make_unique<ColliderSet>(def_.colliders, time());
  for (size_t k = 0; k < std::min(def_.colliders.size(), old.colliders.size()); ++k)
    if (colliders_->hand_offset(k) != Vec3::Zero())
      colliders->hand(k, colliders_->hand_offset(k), time(), time());
  colliders->settle(time());
  colliders_ = std::move(colliders);
  if (def.solver.method != old.solver.method || def.solver.precision != old.solver.precision)
    solver_ = make_solver(def_.solver, model_);
  if (a.long_range.enabled != b.long_range.enabled || a.long_range.slack != b.long_range.slack)
    attachments_->prepare(model_, state_, def_.cloth.long_range);
  try {
    prepare_self_collision();
    prepare_features();
    prepare_solver();
  } catch (const InputError&) {
    reconfigure(old);
    throw;
  }
  rebase_energy();
  return true;
}

void Simulation::grab(int32_t particle) {
  if (particle < 0 || particle >= model_.size()) return;
  if (grabbed_ >= 0) release();
  grabbed_ = particle;
  grabbed_inv_mass_ = state_.inv_mass[particle];
  state_.inv_mass[particle] = 0.0;
  state_.v[particle].setZero();
  // What depends on which particles are free (factorisations, filters) changes at once.
  prepare_solver();
}

void Simulation::move_grab(const Vec3& target) {
  if (grabbed_ < 0 || !target.allFinite()) return;
  state_.x[grabbed_] = target;
  state_.v[grabbed_].setZero();
  solver_->state_changed();
}

void Simulation::release(const Vec3& velocity) {
  if (grabbed_ < 0) return;
  state_.inv_mass[grabbed_] = state_.pinned[grabbed_] ? 0.0 : grabbed_inv_mass_;
  if (!state_.pinned[grabbed_] && velocity.allFinite()) state_.v[grabbed_] = velocity;
  grabbed_ = -1;
  prepare_solver();
  rebase_energy();
}

void Simulation::move_collider(int k, const Vec3& offset) {
  if (k < 0 || k >= static_cast<int>(def_.colliders.size()) || !offset.allFinite()) return;
  colliders_->hand(static_cast<size_t>(k), offset, time(), time() + def_.solver.dt);
}

Vec3 Simulation::collider_offset(int k) const {
  if (k < 0 || k >= static_cast<int>(def_.colliders.size())) return Vec3::Zero();
  return colliders_->hand_offset(static_cast<size_t>(k));
}

void Simulation::set_pinned(int32_t particle, bool pinned) {
  if (particle < 0 || particle >= model_.size()) return;
  state_.pinned[particle] = pinned ? 1 : 0;
  state_.anchor[particle] = state_.x[particle];
  if (particle == grabbed_) {
    grabbed_inv_mass_ = pinned ? 0.0 : 1.0 / model_.mass[particle];
  } else {
    state_.inv_mass[particle] = pinned ? 0.0 : 1.0 / model_.mass[particle];
  }
  state_.v[particle].setZero();
  attachments_->prepare(model_, state_, def_.cloth.long_range);
  prepare_solver();
  rebase_energy();
}

}  // namespace drape
