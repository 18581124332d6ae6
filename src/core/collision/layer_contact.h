// A contact between two layers of the cloth: a vertex over a triangle, or two edges crossing
// over each other, as four particles with coefficients (the pair's offset is Σ coef[k]·x[k])
// and the direction that parts them. Shared by the self-collision stage, which finds and
// resolves such pairs after each collision step, and by the solvers, which hold the pairs the
// stage left touching apart inside their substeps (HeldLayers).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "closest_points.h"
#include "drape/math.h"

namespace drape {

// How far outside a triangle (in barycentric terms) a vertex still counts as over its face:
// a vertex over a corner or an edge is then over every triangle there.
inline constexpr double kFaceMargin = 0.05;
// Edges at a smaller angle than this (its sine) are parallel for edge–edge contacts.
inline constexpr double kLeastSine = 0.1;
// The least share of a pair's weight its free (ungrounded) corners must carry for the pair to
// push off the ground's side alone.
inline constexpr double kLeastShare = 0.25;

/// The inverse masses a pair moves its four particles with, from their own (`inv_mass`) and
/// which of them rest on a collider (bit k of `grounded`): resting ones do not give way to
/// the layers above (mass scaling for stacks, as in Guendelman et al. 2003's shock
/// propagation), unless that leaves the free ones less than kLeastShare of the pair's weight:
/// a corner of weight 0.1 would be thrown ten times the depth, so the pair then moves as if
/// unsupported. Returns Σ coef²·mobility.
inline double pair_mobilities(const double coef[4], const double inv_mass[4], unsigned grounded,
                              double mobility[4]) {
  double weight = 0.0, free_weight = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double c2 = coef[k] * coef[k];
    free_weight += c2 * inv_mass[k];
    if (!(grounded >> k & 1)) weight += c2 * inv_mass[k];
  }
  const bool held = weight >= kLeastShare * free_weight;
  for (int k = 0; k < 4; ++k) mobility[k] = held && (grounded >> k & 1) ? 0.0 : inv_mass[k];
  return held ? weight : free_weight;
}

/// A vertex–triangle pair (kind 0: x[0] the vertex, x[1..3] the triangle) or an edge–edge
/// pair (kind 1: x[0]–x[1] and x[2]–x[3]) at positions x: its coefficients and the unit normal
/// of the triangle ((x2 − x1) × (x3 − x1)) or of both edges ((x1 − x0) × (x3 − x2)). Not
/// valid where it has none: a vertex beside the face (left to the edge–edge pairs of its
/// edges), edges whose nearest points are not inside both (a corner: the vertex–triangle
/// pairs'), nearly parallel edges (whose ends' vertex–triangle pairs hold them apart), or a
/// degenerate triangle. The coefficients are set even where it is not valid.
struct LayerStencil {
  double coef[4] = {1.0, 0.0, 0.0, 0.0};
  Vec3 normal = Vec3::UnitY();
  bool valid = false;
};

/// An edge–edge pair's stencil (kind 1 of layer_stencil) from its nearest points `sp`
/// (closest_between_segments of x), for a caller that has them already.
inline LayerStencil edge_stencil(const Vec3 x[4], const SegmentPoints& sp) {
  LayerStencil st;
  st.coef[0] = 1 - sp.s, st.coef[1] = sp.s, st.coef[2] = -(1 - sp.t), st.coef[3] = -sp.t;
  if (!sp.interior) return st;
  // Along the normal of both edges (Bridson et al. 2002): the offset between the nearest
  // points turns wildly as two edges nearly touch.
  const Vec3 e = x[1] - x[0], f = x[3] - x[2];
  const Vec3 normal = e.cross(f);
  const double length = normal.norm();
  if (!(length > kLeastSine * e.norm() * f.norm())) return st;
  st.normal = normal / length;
  st.valid = true;
  return st;
}

/// A vertex–triangle pair's stencil (kind 0 of layer_stencil) from where the vertex lies over
/// the face, `q` (over_face of x with kFaceMargin), for a caller that has it already.
inline LayerStencil face_stencil(const Vec3 x[4], const TrianglePoint& q) {
  LayerStencil st;
  st.coef[1] = -q.wa, st.coef[2] = -q.wb, st.coef[3] = -q.wc;
  // Pushed along the triangle's normal only, so contacts never squeeze the cloth in its own
  // plane.
  if (!q.interior) return st;
  const Vec3 normal = (x[2] - x[1]).cross(x[3] - x[1]);
  const double length = normal.norm();
  if (!(length > 0.0)) return st;
  st.normal = normal / length;
  st.valid = true;
  return st;
}

inline LayerStencil layer_stencil(int kind, const Vec3 x[4]) {
  if (kind != 0) return edge_stencil(x, closest_between_segments(x[0], x[1], x[2], x[3]));
  return face_stencil(x, over_face(x[0], x[1], x[2], x[3], kFaceMargin));
}

/// The pairs the self-collision stage left touching at the end of its last collision step,
/// each with the side of its stencil's normal it lay on, held at least `thickness` apart on
/// that side inside the solver's next substeps, with Coulomb friction on their slide. A layer
/// resting on another then rests in the solve, gravity against its contacts, instead of
/// sinking a part's fall into the layer below for the stage to push back after the solve; the
/// stage still finds and resolves what the solve leaves close or crossing.
class HeldLayers {
 public:
  struct Pair {
    int32_t index[4];
    uint8_t kind;      ///< 0 vertex–triangle, 1 edge–edge (LayerStencil)
    int8_t side;       ///< ±1: the side of the stencil's normal the pair lies on
    uint8_t grounded;  ///< bit k: particle k rested on a collider (it does not give way)
  };
  std::vector<Pair> pairs;
  double thickness = 0.0;
  double friction = 0.0;

  bool any() const { return !pairs.empty(); }

  /// Whether substep k of `steps` holds them: every substep of a method that takes few, but
  /// at most kPasses evenly spread over a frame, the last always. Between two passes a layer
  /// at rest sinks by gravity's ½g·t² (a micrometre over a sixty-fourth of a frame), and each
  /// pass leaves the pairs no velocity toward each other; a pass over every pair, serial,
  /// costs what a few of xpbd's parallel substeps do (README, Self-collision, for the figures).
  static constexpr int kPasses = 64;
  static bool due(int k, int steps) {
    const int every = (steps + kPasses - 1) / kPasses;
    return (k + 1) % every == 0 || k + 1 == steps;
  }

  /// Pushes every pair closer than the thickness apart, on its side, serially. `Cloth`
  /// offers position(i), inv_mass(i), moved(i) (its move since the substep began), add(i, d)
  /// (a move, which the substep's velocity takes) and shift(i, d) (of where the substep
  /// began too, which it does not). A pair found deeper than a thickness on the other side came
  /// round an edge, not through: the stage's business.
  template <class Cloth>
  void apply(Cloth& cloth) const {
    for (const Pair& p : pairs) {
      Vec3 x[4];
      for (int k = 0; k < 4; ++k) x[k] = cloth.position(p.index[k]);
      const LayerStencil st = layer_stencil(p.kind, x);
      if (!st.valid) continue;
      const Vec3 n = p.side * st.normal;
      Vec3 offset = Vec3::Zero();
      for (int k = 0; k < 4; ++k) offset += st.coef[k] * x[k];
      const double separation = n.dot(offset), depth = thickness - separation;
      if (!(depth > 0.0) || separation < -thickness) continue;
      double inv_mass[4], mobility[4];
      for (int k = 0; k < 4; ++k) inv_mass[k] = cloth.inv_mass(p.index[k]);
      const double weight = pair_mobilities(st.coef, inv_mass, p.grounded, mobility);
      if (!(weight > 0.0)) continue;
      // A grounded corner's move this substep is the ground's to undo (its contacts come
      // next): as seen from the layer above, it stays.
      auto moved_over = [&](int k) {
        return mobility[k] > 0.0 ? Vec3(st.coef[k] * cloth.moved(p.index[k])) : Vec3::Zero();
      };
      Vec3 moved = Vec3::Zero();
      for (int k = 0; k < 4; ++k) moved += moved_over(k);
      // What the pair approached by this substep is undone as a move (it leaves the pair no
      // velocity toward each other: inelastic); what it lay closer than the thickness before
      // is a shift of where the substep started, which gives it no velocity apart.
      const double approach = std::clamp(-n.dot(moved), 0.0, depth);
      for (int k = 0; k < 4; ++k) {
        const Vec3 unit = (st.coef[k] * mobility[k] / weight) * n;
        cloth.add(p.index[k], approach * unit);
        cloth.shift(p.index[k], (depth - approach) * unit);
      }
      if (friction <= 0.0) continue;
      // Coulomb friction on the pair's slide this substep: cancelled within friction × the
      // approach undone (the normal impulse's share of the substep; the shift is not a force).
      Vec3 slide = Vec3::Zero();
      for (int k = 0; k < 4; ++k) slide += moved_over(k);
      slide -= slide.dot(n) * n;
      const double length = slide.norm(), grip = friction * approach;
      if (!(length > 0.0)) continue;
      const double cancel = length <= grip ? 1.0 : grip / length;
      for (int k = 0; k < 4; ++k)
        cloth.add(p.index[k], (-cancel * st.coef[k] * mobility[k] / weight) * slide);
    }
  }
};

}  // namespace drape
