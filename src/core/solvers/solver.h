// The solver interface: each method advances the whole state by one frame, splitting it into
// substeps as the method needs. Methods share forces.h and collider.h.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "collision/collider_set.h"
#include "collision/feature_contacts.h"
#include "collision/layer_contact.h"
#include "drape/cloth.h"
#include "drape/collider.h"
#include "drape/scene.h"
#include "drape/simulation.h"

namespace drape {

class LongRange;

/// Everything a solver reads and writes during a frame.
struct World {
  const ClothModel& model;
  ClothState& state;
  const ForcesDef& forces;
  /// The colliders posed for the present substep (see pose_colliders), a sweep's poses included.
  const std::vector<Collider>& colliders;
  double time;                  ///< s, at the start of the frame
  const LongRange& attachments;  ///< long-range attachments to apply (cloth.long_range)
  const std::atomic<bool>* stop = nullptr;  ///< when it turns true, the frame stops early
  bool cut_short = false;                   ///< set by the solver that stopped early
  ColliderSet* moving = nullptr;            ///< the colliders when some move; null when none does
  const ColliderSet* bodies = nullptr;      ///< the colliders, moving or still (null: none given)
  /// The cloth's pairs with boxes' and meshes' sharp features this frame; null when none can
  /// meet. Each method applies it after its particle contacts.
  const FeatureContacts* features = nullptr;
  /// With self-collision: the layers the stage left touching, to hold apart in the substeps
  /// (HeldLayers::due) before the colliders' contacts; null when there are none or the method
  /// leaves them to the stage (Solver::holds_layers).
  const HeldLayers* held = nullptr;

  /// The drag per particle and the air density the cloth feels (ForcesDef's, or the defaults
  /// for a cloth with or without a material), and whether drag on its area acts.
  double air_drag() const { return forces.air_drag_for(model.material); }
  double air_density() const { return forces.air_density_for(model.material); }
  bool area_drag() const { return air_density() > 0.0 && forces.drag_coefficient > 0.0; }

  /// Whether pose_colliders does anything (some collider moves).
  bool colliders_move() const { return moving != nullptr; }
  /// Poses the colliders for the substep from t0 to t1 (s): each method calls it at the start
  /// of every substep, so moving bodies are where they are at that substep's end.
  void pose_colliders(double t0, double t1) {
    if (moving) moving->pose(t0, t1);
  }

  /// Called between substeps: whether to stop here, leaving the frame part done (the stop flag
  /// is up). Records that the frame was cut short.
  bool stop_here() {
    if (stop && stop->load(std::memory_order_relaxed)) cut_short = true;
    return cut_short;
  }
};

class Solver {
 public:
  virtual ~Solver() = default;
  /// Called before the first frame and whenever the model, pins, masses or settings change.
  /// Sizes the workspace (step_frame allocates nothing, tests/allocation_test.cpp; but for
  /// what a step finds growing, such as contacts, `implicit`'s factor, set up the first time
  /// CG is slow, and a factorisation's work rows beyond SparseCholesky's 16 384). Throws
  /// InputError if the method cannot run this set-up (e.g. too many substeps).
  virtual void prepare(const World& world, const SolverDef& def) = 0;
  /// Advances one frame of dt, or part of it: between substeps it asks world.stop_here() and
  /// stops when told to. A dt shorter than the frame's (a collision step's part) takes its
  /// share of the frame's substeps (substeps_in). Leaves state.normal up to date.
  virtual void step_frame(World& world, double dt) = 0;
  /// Says that the state was changed since the last frame other than by step_frame or a
  /// prepare() (the hand moved a held particle). A method that keeps the state in arrays of its
  /// own from one frame to the next must read it again.
  virtual void state_changed() {}
  virtual int substeps() const = 0;
  /// Heap bytes of the method's own arrays (its workspace, factorisations included), as sized
  /// by the last prepare(): what the method adds to the model and state, for memory reports.
  virtual int64_t workspace_bytes() const = 0;
  /// Whether the springs' elastic energy in the state this method leaves is energy the method
  /// put there. True for an exact explicit update; false for methods that stop iterating short
  /// of convergence (their leftover stretch is solver error), so the divergence watch leaves
  /// spring energy out of its budget for them and watches kinetic energy.
  virtual bool stretch_is_energy() const { return false; }
  /// Whether one step can pull springs far past their rest length while the kinetic energy
  /// stays small: a linearised solve (`implicit`'s one Newton step) whose springs do not see a
  /// force taken outside it. The divergence watch then also counts the energy of the springs
  /// stretched past twice their rest length, which no inaccuracy of a step explains.
  virtual bool may_tear() const { return false; }
  /// Whether step_frame may be given a dt other than the one prepare() saw (a part of a frame,
  /// for self-collision's collision steps). False for a method that factorised its matrix
  /// for one step.
  virtual bool steps_any_dt() const { return true; }
  /// Whether the method holds the layers self-collision left touching apart in its substeps
  /// (World::held); the stage gathers them only for a method that does.
  virtual bool holds_layers() const { return false; }
  /// What the auto method chose and how often it changed it; null for the other methods.
  virtual const AutoChoice* auto_choice() const { return nullptr; }
};

/// The method def.method names, for this model (xpbd has a path of its own for grids).
std::unique_ptr<Solver> make_solver(const SolverDef& def, const ClothModel& model);

/// A whole count held in a double (a substep count a set-up would need, possibly huge or
/// infinite), written for a message: "10700", "inf".
std::string count_text(double count);

/// The steps a frame takes in `fast` and `implicit` (one-step methods whose contacts come after
/// their solve) where the cloth can meet a collider's sharp features (a box's or a mesh's edges
/// and corners, an open sheet's rim; World::features). The features' pushes come after the
/// solve, which does not know them. At one step a frame a coarse cloth dropped over a box's
/// corner tore `implicit` in 14 of 27 drops (2 steps: 1; 4: none), and an open sheet's rim cut
/// the cloth in 26 of 36 drops with `fast` (2 steps: 10; 4: none). Over 120 drops onto the
/// sheet (tilted 5° to 15°, turned 15° to 45°, friction 0.1 or 0.2, grid and mesh) `fast` at 4
/// was cut in none, `implicit` at 4 in 6, at 6 and 8 in none: colliders_test.cpp's drops.
constexpr int kFastStepsAtSharpFeatures = 4;
constexpr int kImplicitStepsAtSharpFeatures = 6;

/// The substeps a step of dt takes in a method that takes `per_frame` in a frame of frame_dt:
/// the step's share of them, rounded up. A part of a frame (self-collision's collision steps)
/// then runs substeps as long as the frame's, not `per_frame` shorter ones: split into eight
/// parts, a frame would otherwise cost eight frames.
int substeps_in(double dt, double frame_dt, int per_frame);

/// Air drag over a step h on the velocities, semi-implicit (stable at any h): the seed's per
/// particle, and the material's on the cloth's area.
void apply_air_drag(World& world, double h);
/// The end of a velocity-level substep shared by `symplectic` and `implicit`: the drift
/// x += h·v, long-range attachments, then contacts (last, so nothing stays inside a collider).
/// Pinned and held particles (1/m = 0) stay put.
void drift_constrain(World& world, double h);
/// Every contact of the state with the colliders: particles, triangles against moving round
/// bodies, the pairs with sharp features (world.features).
void resolve_all_contacts(World& world);
std::unique_ptr<Solver> make_symplectic();
std::unique_ptr<Solver> make_implicit();
/// xpbd on the grid's own layout (its row and column fast paths), or on any mesh.
std::unique_ptr<Solver> make_grid_xpbd(Precision precision);
std::unique_ptr<Solver> make_mesh_xpbd(Precision precision);
std::unique_ptr<Solver> make_fast();
std::unique_ptr<Solver> make_auto();
/// auto for a material's cloth: xpbd or implicit, by xpbd's automatic substeps.
std::unique_ptr<Solver> make_material_auto();

/// The largest explicit step h with h²ω² + 2hγ < 4, where ω² = max_i Σ_s 2k_s/m_i and
/// γ = max_i Σ_s 2c_s/m_i over the springs s at each free particle i (Gershgorin bounds on the
/// stiffness and damping matrices scaled by the inverse mass). This holds for the whole cloth;
/// the single-spring bound 2·sqrt(m/k) does not. Infinite when nothing is free or stiff.
double explicit_step_bound(const ClothModel& model, const std::vector<double>& inv_mass);

}  // namespace drape
