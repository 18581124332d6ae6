// Long-range attachments (Kim, Chentanez & Müller-Fischer 2012, "Long range attachments – a
// method to simulate inextensible clothing in computer games"): a unilateral distance limit
// between a free particle and a pin, |x_p − x_pin| ≤ (1 + slack)·L_p,pin with L the rest
// distance along the cloth (the geodesic on its rest shape, not the straight line: a tube's
// hem hangs from its waist along the tube). Each particle is tethered to its kMaxTethers nearest
// pins along the cloth (to every pin when there are no more). They stop mass–spring cloth from
// stretching like rubber under its own weight at any stiffness, iteration count or step.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "drape/cloth.h"
#include "drape/scene.h"

namespace drape {

/// Projects x onto the ball of radius `limit` around `anchor` if it lies outside (a pin has
/// infinite mass, so only x moves). Returns the unit direction from the anchor when it
/// projected, zero otherwise.
inline Vec3 project_attachment(const Vec3& anchor, double limit, Vec3& x) {
  const Vec3 d = x - anchor;
  const double len2 = d.squaredNorm();
  if (len2 <= limit * limit) return Vec3::Zero();
  const double len = std::sqrt(len2);
  const Vec3 u = d / len;
  x = anchor + limit * u;
  return u;
}

/// Removes the outward velocity along u (no-op for u = 0): the constraint is at its limit, so
/// motion outward would be undone next step; removing it (never adding) injects no energy.
inline void clamp_outward_velocity(const Vec3& u, Vec3& v) {
  const double vn = v.dot(u);
  if (vn > 0.0) v -= vn * u;
}

/// The attachments of one cloth: each particle's tethers to pins. Rebuilt whenever pins change.
class LongRange {
 public:
  static constexpr int kMaxTethers = 4;  ///< tethers per particle, to its nearest pins

  /// Collects the pinned particles (state.pinned) and measures each particle's tethers when
  /// `def.enabled`; nothing otherwise.
  void prepare(const ClothModel& model, const ClothState& state, const LongRangeDef& def);
  bool active() const { return !pins_.empty(); }
  /// Tethers per particle (slots: a particle with fewer has pin −1 in the rest).
  int tethers() const { return tethers_; }
  /// The pin of particle p's tether t (increasing with t), or −1.
  int32_t pin(int32_t p, int t) const { return pin_[static_cast<size_t>(p) * tethers_ + t]; }
  /// The largest distance allowed between particle p and its tether t's pin, m.
  double limit(int32_t p, int t) const { return limit_[static_cast<size_t>(p) * tethers_ + t]; }
  /// Whether tether t of every particle is pins()[t] (few pins, all reached): solvers may then
  /// treat a tether slot as one pin.
  bool uniform() const { return uniform_; }
  /// Projects every free particle onto its limits (tethers in order) and, when `fix_velocity`,
  /// removes the outward velocity along each limit it hit. In parallel over particles;
  /// deterministic.
  void apply(ClothState& state, bool fix_velocity) const;
  /// Projects one position xp of free particle p onto its limits (pins at x), in the same order.
  void project(const std::vector<Vec3>& x, int32_t p, Vec3& xp) const {
    for (int t = 0; t < tethers_ && pin(p, t) >= 0; ++t)
      project_attachment(x[pin(p, t)], limit(p, t), xp);
  }
  /// Whether position xp of free particle p lies beyond, or within `reach` of, one of its limits
  /// (pins at x).
  bool within_reach(const std::vector<Vec3>& x, int32_t p, const Vec3& xp, double reach) const {
    for (int t = 0; t < tethers_ && pin(p, t) >= 0; ++t)
      if ((xp - x[pin(p, t)]).norm() > limit(p, t) - reach) return true;
    return false;
  }
  /// The pinned particles, in increasing order.
  const std::vector<int32_t>& pins() const { return pins_; }
  /// Heap bytes held.
  int64_t bytes() const { return heap_bytes(pins_, pin_, limit_); }

 private:
  std::vector<int32_t> pins_;
  int tethers_ = 0;
  std::vector<int32_t> pin_;   ///< per particle and tether: the pin, or −1
  std::vector<double> limit_;  ///< per particle and tether: (1 + slack) × the rest distance
  bool uniform_ = false;
};

}  // namespace drape
