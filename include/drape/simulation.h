// The simulation: one cloth, its forces and colliders, advanced a frame at a time.
//
//   drape::SceneDef def;                 // documented defaults: the `hang` scene
//   def.cloth.cols = def.cloth.rows = 64;
//   drape::Simulation sim(def);          // throws drape::InputError on bad input
//   while (sim.time() < 5.0 && sim.step()) draw(sim.state().x, sim.model().triangles);
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "drape/cloth.h"
#include "drape/collider.h"
#include "drape/scene.h"

namespace drape {

class Solver;
class LongRange;
class SelfCollision;
struct World;
class ColliderSet;
class FeatureContacts;

/// Figures that describe the state; cheap enough to take once per frame.
struct Diagnostics {
  double kinetic_energy = 0.0;   ///< J
  double max_strain = 0.0;       ///< max |length/rest − 1| over structural springs
  double mean_strain = 0.0;      ///< mean of the same
  double p99_strain = 0.0;       ///< 99th percentile of the same
  double max_penetration = 0.0;  ///< m, deepest particle inside a collider's surface (0 if none)
  double pinned_drift = 0.0;     ///< m, largest distance of a pinned particle from its anchor
  bool finite = true;            ///< every position, velocity and figure above is finite
};

/// What the auto method chose for the scene and how it adapted: the method and settings it
/// steps with now, and how often it raised and lowered its effort.
struct AutoChoice {
  Method method = Method::xpbd;
  Precision precision = Precision::f32;
  int substeps = 0;      ///< per frame
  int line_passes = 0;   ///< xpbd's solver.line_passes
  int stiff_sweeps = 0;  ///< xpbd's solver.stiff_sweeps
  int raises = 0;        ///< times it raised its effort
  int lowers = 0;        ///< times it lowered it
  double strain = 0.0;   ///< the largest structural strain after the last frame
  /// More effort stopped lowering the strain while it was above the tolerance: what is left is
  /// the springs' own stretch (soft springs, point pins without attachments), out of reach.
  bool out_of_reach = false;
};

/// What self-collision did in the last frame (cloth.self_collision).
struct SelfCollisionReport {
  int64_t contacts = 0;         ///< vertex–triangle and edge–edge pairs found close or crossed
  int64_t crossings = 0;        ///< crossing pairs after the contact passes
  int64_t zone_vertices = 0;    ///< vertices moved rigidly in impact zones
  int64_t frozen_vertices = 0;  ///< vertices held at their start positions
  int64_t left = 0;  ///< crossing pairs left at the end (0 unless kinematic particles caused them)
};

/// Heap memory the simulation holds, in bytes (vectors counted by capacity).
struct MemoryUse {
  int64_t state = 0;      ///< positions, velocities, pins, normals, areas
  int64_t model = 0;      ///< springs, triangles and adjacency, rest shape, masses
  int64_t workspace = 0;  ///< the solver's arrays and factorisations, and the simulation's own
  int64_t total() const { return state + model + workspace; }
  /// total() shared out over `particles` (0 for none).
  double per_particle(int64_t particles) const {
    return particles > 0 ? static_cast<double>(total()) / static_cast<double>(particles) : 0.0;
  }
};

/// How many particles the cloth `def` describes will have (grid: cols × rows; mesh: vertices).
int64_t particle_count(const ClothDef& def);

/// An upper estimate of Simulation(def).memory().total(), for budgets checked before building:
/// per particle, the state and model (about 450 bytes) plus the method's workspace, which for
/// `fast` includes its sparse Cholesky factor (fill grows like log n on a grid).
int64_t estimated_memory(const SceneDef& def);

class Simulation {
 public:
  /// Builds the cloth and the solver. Throws InputError if `def` fails check(), if the cloth
  /// starts inside a collider (deeper than its thickness plus the cloth's perturbation), or if
  /// the solver cannot run it (e.g. more automatic substeps than solver.max_substeps).
  explicit Simulation(const SceneDef& def);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  /// Advances one frame of solver.dt. Returns false once the state has diverged (non-finite or
  /// overflowing positions, velocities or energies, or kinetic energy beyond what gravity, wind
  /// and the user's hand could have supplied);
  /// the state is then left as it was at detection and later calls do nothing. Never throws.
  bool step();

  /// Lets a frame stop part way: once `*flag` turns true (a signal handler may set it), step()
  /// returns at the end of the substep under way, leaving the state between two frames and
  /// frame() where it was; stopped() then says so. Null (the default): frames always finish.
  /// The flag must outlive the simulation's use of it.
  void set_stop_flag(const std::atomic<bool>* flag) { stop_ = flag; }
  /// The last step() stopped part way through its frame.
  bool stopped() const { return stopped_; }
  /// The stop flag is up. A method with one substep a frame finishes every frame it starts, so
  /// a caller stepping until something happens asks this as well as stopped().
  bool stop_requested() const { return stop_ && stop_->load(std::memory_order_relaxed); }

  bool diverged() const { return !divergence_.empty(); }
  const std::string& divergence() const { return divergence_; }  ///< why, with a hint
  int64_t diverged_frame() const { return diverged_frame_; }     ///< -1 unless diverged

  int64_t frame() const { return frame_; }
  double time() const { return static_cast<double>(frame_) * def_.solver.dt; }
  int substeps_per_frame() const;
  /// With solver.method "auto": what it chose and how it adapted; null otherwise.
  const AutoChoice* auto_choice() const;
  const SceneDef& def() const { return def_; }
  const ClothModel& model() const { return model_; }
  const ClothState& state() const { return state_; }
  /// The colliders where they are now (moving ones at the present time).
  const std::vector<Collider>& colliders() const;
  Diagnostics diagnostics() const;
  MemoryUse memory() const;
  /// With cloth.self_collision on: what it did in the last frame; null when it is off.
  const SelfCollisionReport* self_collision() const;

  /// Applies a changed definition. Forces, colliders, spring parameters, mass and solver
  /// settings take effect at once; returns false (and changes nothing) when the change needs a
  /// new cloth (resolution, size, origin, orientation, mesh, transform, pins, perturbation):
  /// build a new Simulation then. Throws InputError if `def` fails check().
  bool reconfigure(const SceneDef& def);

  /// The seed's mouse drag: grab() holds a particle still, move_grab() places it (velocity zero),
  /// release() lets it go with the given velocity (zero: the seed's; the hand's: a flick).
  void grab(int32_t particle);
  void move_grab(const Vec3& target);
  void release(const Vec3& velocity = Vec3::Zero());
  int32_t grabbed() const { return grabbed_; }  ///< -1 when nothing is held

  /// The hand moves collider k (the viewer's Shift-drag): it is carried `offset` (m) from where
  /// its definition and motion put it, getting there over the next frame, so the cloth it
  /// touches feels the hand's velocity. Ignored for a k out of range or a non-finite offset.
  void move_collider(int k, const Vec3& offset);
  /// Where the hand has carried collider k (zero until it does).
  Vec3 collider_offset(int k) const;

  /// Pins a particle where it is now, or frees it.
  void set_pinned(int32_t particle, bool pinned);

 private:
  void prepare_solver();
  void prepare_self_collision();
  /// Places the particles of pins that move where their motions have them at time t (s),
  /// with the velocity of getting there over the last dt; returns whether any moved.
  bool move_pins(double t, double dt);
  void step_with_self_collision(World& world);
  /// Sets up the contacts with colliders' sharp features (none when no collider has any).
  void prepare_features();
  /// Steps the solver over dt from the state and colliders as they are, with the feature
  /// contacts gathered for it.
  void solve(World& world, double dt);
  void rebase_energy();
  double mechanical_energy() const;

  SceneDef def_;
  ClothModel model_;
  ClothState state_;
  std::unique_ptr<ColliderSet> colliders_;
  std::unique_ptr<LongRange> attachments_;  ///< rebuilt when the pins change
  std::unique_ptr<Solver> solver_;
  std::unique_ptr<SelfCollision> self_collision_;  ///< null unless cloth.self_collision is on
  std::unique_ptr<FeatureContacts> features_;      ///< null unless a collider has sharp features
  std::vector<double> travel_;                     ///< m, each collider's travel this frame
  std::vector<Vec3> frame_start_;                  ///< positions at the start of a collision step
  double frame_motion_ = 0.0;  ///< m, how far close layers moved past each other last frame
  /// Each pin entry's particles and where they started (pins with a motion follow it).
  struct PinEntry {
    std::vector<int32_t> particles;
    std::vector<Vec3> start;     ///< m
    Vec3 centre = Vec3::Zero();  ///< m, of `start`: what a motion turns about
  };
  std::vector<PinEntry> pin_entries_;
  bool pins_move_ = false;
  std::vector<double> scratch_;
  double diagonal_ = 0.0;  ///< m, of the rest shape's bounding box (divergence tolerance)
  double total_mass_ = 0.0;  ///< kg, the cloth's (a material's is not cloth.mass)
  int64_t frame_ = 0;
  const std::atomic<bool>* stop_ = nullptr;
  bool stopped_ = false;
  int32_t grabbed_ = -1;
  double grabbed_inv_mass_ = 0.0;
  // Divergence watch: mechanical energy may not grow past what was there at the last rebase
  // plus the work external forces did since.
  double energy_ref_ = 0.0;
  double external_work_ = 0.0;
  std::string divergence_;
  int64_t diverged_frame_ = -1;
};

}  // namespace drape
