// Self-collision: the stage after each frame's solve that keeps the cloth from passing through
// itself, whatever the method. It works on the frame's start and end positions, as Bridson,
// Fedkiw & Anderson (2002, "Robust treatment of collisions, contact and friction for cloth
// animation") do with their collision step around any internal dynamics:
//
//  1. Contacts. Vertex–triangle and edge–edge pairs closer than the thickness at the end of the
//     frame, or whose sides changed during it, are found through a grid over the swept boxes;
//     pairs inside one part of the cloth that is smooth at the frame's end (a disk whose normals
//     lie within a cone and which projects one to one: smooth_patches.h) are not looked for.
//     Each is pushed apart to the thickness on the side it started the frame on, with Coulomb
//     friction on the relative slide, in a few Gauss–Seidel passes (a position-based
//     repulsion: Müller et al. 2007; Macklin et al. 2014). Colliders are enforced after each
//     pass, so a lower layer is not pushed into the ground. After a method that held the
//     layers in its substeps (item 4), the threads (structural springs) at the contacts are
//     swept back between the passes to the lengths the solver left them, so that the pushes
//     move layers instead of stretching the cloth: alone, they left a stiff pile's frames 2 to
//     4% stretched where the solver had left 1% (README, Self-collision).
//  2. Fail-safe: rigid impact zones. Triangle pairs that still cross (the certified test of
//     count_self_intersections) join their vertices into zones, which move rigidly from their
//     start positions with the zone's linear and angular momentum (Provot 1997; Bridson 2002).
//     A rigid motion of a crossing-free start crosses nothing inside the zone; pairs between
//     zones and the rest merge zones, and the check repeats.
//  3. Last resort: zones that still cross after a few rounds stay where they started the frame,
//     at rest. Frozen triangles cannot cross each other (they did not at the start), and every
//     round freezes at least one more vertex, so the loop ends with no crossing pair.
//  4. Held in the solve: the pairs left within reach go to the solver for the next part
//     (hold_layers; collision/layer_contact.h), which keeps them a thickness apart inside its
//     substeps, so that layers resting on each other rest in the solve.
//
// Velocities change with the positions (Δx/dt: contacts end inelastic), rigid zones take the
// zone's velocity, frozen vertices stop. The promise holds when the frame starts free of
// crossings and its kinematic particles (pins, the held one) are the ones that caused none.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "box_grid.h"
#include "crossings.h"
#include "drape/cloth.h"
#include "drape/collider.h"
#include "drape/simulation.h"
#include "layer_contact.h"
#include "smooth_patches.h"

namespace drape {

/// The thickness the definition asks for on this cloth: its own, or a quarter of the mean edge.
double self_collision_thickness(const SelfCollisionDef& def, const ClothModel& model);

class SelfCollision {
 public:
  /// Sets up for the cloth (its edges) with the gap and friction to keep.
  void prepare(const ClothModel& model, double thickness, double friction);

  /// Acts on the state the solver left at the end of a frame of dt that began at positions
  /// `start`, as the header describes; `solver_held_layers` where the method held the last
  /// hold_layers() pairs in its substeps (its threads are then kept between the pushes).
  /// Leaves state.normal up to date. Returns whether it changed the state.
  bool resolve(const ClothModel& model, const std::vector<Vec3>& start,
               const std::vector<Collider>& colliders, double dt, ClothState& state,
               bool solver_held_layers);

  /// How many collision steps a frame needs whose layers move by `motion` (m) relative to each
  /// other where they come close: enough that they move a fraction of the thickness at most
  /// between two steps, at most kMaxParts.
  int parts_for(double motion) const;
  static constexpr int kMaxParts = 8;
  /// How far the solver moved the last resolve()'s contacts past each other over its frame
  /// (the most of any contact's vertex and a corner of its triangle, or the first ends of its
  /// two edges), m: the slide and the push into a layer the contacts then undo, the larger the
  /// more the undoing strains the cloth. Layers apart do not count, nor does a cloth moving as
  /// one or rippling where it lies in one layer.
  double near_motion() const { return near_motion_; }

  /// The last resolve()'s pairs still within reach of each other in `state` (the state it
  /// left, the next part's start), each on the side it lies on, for the solver to hold apart
  /// inside its substeps (HeldLayers); particles on a `colliders` surface do not give way.
  const HeldLayers& hold_layers(const ClothModel& model, const ClothState& state,
                                const std::vector<Collider>& colliders);

  const SelfCollisionReport& report() const { return report_; }
  double thickness() const { return thickness_; }
  int64_t bytes() const;

 private:
  /// A vertex–triangle (kind 0: a = the vertex, b = the triangle) or edge–edge (kind 1: a and b
  /// edges) pair, in the order found.
  struct Contact {
    int32_t a, b;
    uint8_t kind;
  };
  /// A contact as four particles with coefficients: the pair's separation is
  /// dir · Σ coef[k]·x[index[k]], dir pointing to the side the pair started the frame on.
  struct Stencil {
    int32_t index[4];
    double coef[4];
    Vec3 dir;
    double side = 1.0;  ///< dir is side × the LayerStencil's normal
    double separation = 0.0;
    bool valid = false;  ///< false where no direction is defined (degenerate)
  };
  /// The contact's four particles: the vertex and the triangle's corners, or both edges' ends.
  void particles_of(const Contact& c, const ClothModel& model, int32_t index[4]) const;
  Stencil stencil(const Contact& c, const ClothModel& model, const std::vector<Vec3>& start,
                  const std::vector<Vec3>& x) const;
  /// Fills the inverse masses a contact moves its four particles with (pair_mobilities) and
  /// returns Σ coef²·mobility.
  double mobilities(const Stencil& st, const ClothState& state, double mobility[4]) const;
  /// Bit k set where particle index[k] rests on a collider (mobility_ zero).
  unsigned grounded_bits(const int32_t index[4]) const;
  /// mobility_: each particle's inverse mass, zero where it rests on a collider.
  void ground(const ClothModel& model, const ClothState& state,
              const std::vector<Collider>& colliders);
  void find_contacts(const ClothModel& model, const std::vector<Vec3>& start,
                     const std::vector<Vec3>& x);
  void push_apart(const Contact& c, const ClothModel& model, const std::vector<Vec3>& start,
                  ClothState& state) const;
  bool remove_crossings(const ClothModel& model, const std::vector<Vec3>& start, double dt,
                        ClothState& state);
  /// Sets crossing_ to the pairs that cross in x: only those with a triangle at a contact or
  /// moved since the search where the search has shown that no other pair can cross.
  void find_crossings(const ClothModel& model, const std::vector<Vec3>& x);
  /// Marks the particles of every pair found, contacts and near_ (touched_).
  void touch(const ClothModel& model);
  /// Lists the threads (structural springs) at the touched particles, each with the length
  /// the solver left it (state.x before the contacts move anything).
  void gather_threads(const ClothState& state);
  /// One Gauss–Seidel sweep over those threads back to their lengths, moving particles by
  /// mobility_ (a grounded or pinned end stays).
  void keep_lengths(ClothState& state) const;

  double thickness_ = 0.0;
  double friction_ = 0.0;
  double near_motion_ = 0.0;
  /// Set by find_contacts: every triangle's inradius is under the reach at the frame's end. An
  /// edge of one triangle through another's inside then passes within that inradius of the
  /// other's nearest edge (no point inside a triangle is farther from all its edges), a pair
  /// sharing no vertex: a crossing leaves an edge–edge pair in the search (in contacts_ or
  /// near_), and no pair found means none.
  /// Set too where the cloth is one smooth patch at the frame's end, which crosses nothing.
  bool crossings_leave_contacts_ = false;
  std::vector<std::array<int32_t, 2>> edges_;
  std::vector<Box> face_boxes_, edge_boxes_;  ///< face_boxes_: the triangles', then the vertices'
  std::vector<uint8_t> boxed_;                ///< per triangle: its corners finite, it has a box
  std::vector<uint8_t> finite_;               ///< per vertex: finite at both ends of the frame
  SmoothPatches patches_;
  std::vector<int32_t> kept_faces_, kept_edges_;
  BoxGrid face_grid_, edge_grid_;
  std::vector<Contact> contacts_;  ///< the pairs found whose stencil has a direction: they act
  /// The pairs found within reach whose stencil has none there (nearest points on a boundary):
  /// they push nothing, but a crossing's edge pair may be among them (touch).
  std::vector<Contact> near_;
  ThreadLists<Contact> found_, found_near_;  ///< each thread's, gathered into contacts_, near_
  std::vector<Vec3> solved_;      ///< the positions the solver left, for the velocity change
  std::vector<double> mobility_;  ///< per particle, the inverse mass contacts move it with
  std::vector<Vec3> contacted_;   ///< the positions the contacts left, for zones' momenta
  std::vector<std::array<int32_t, 2>> threads_;  ///< the structural springs' particles
  std::vector<int32_t> touched_threads_;         ///< gather_threads: those at a contact
  std::vector<double> thread_lengths_;           ///< ... and their lengths after the solve
  std::vector<uint8_t> touched_;                 ///< per particle: in a contact (touch)
  HeldLayers held_;
  CrossingFinder crossing_finder_;
  std::vector<TrianglePair> crossing_;
  std::vector<uint8_t> suspect_;     ///< per triangle: may cross (find_crossings)
  std::vector<int32_t> zone_;        ///< union–find parent per vertex (itself: a root)
  std::vector<uint8_t> zone_state_;  ///< 0 free, 1 in a rigid zone, 2 frozen
  std::vector<int32_t> zoned_;       ///< vertices in zones, this frame
  SelfCollisionReport report_;
};

}  // namespace drape
