// Long-range attachments (Kim, Chentanez & Müller-Fischer 2012, "Long range attachments – a
// method to simulate inextensible clothing in computer games"): a unilateral distance limit
// between each free particle and each pin, |x_p − x_pin| ≤ (1 + slack)·L_p,pin with L the rest
// distance along the cloth. It stops mass–spring cloth from stretching like rubber under its
// own weight at any stiffness, iteration count or step, for the cost of one pass.
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

/// The attachments of one cloth: the pins they hang from. Rebuilt whenever pins change.
class LongRange {
 public:
  /// Collects the pinned particles (state.pinned) when `def.enabled`; nothing otherwise.
  void prepare(const ClothModel& model, const ClothState& state, const LongRangeDef& def);
  bool active() const { return !pins_.empty(); }
  /// Projects every free particle onto its limits (pins in a fixed order) and, when
  /// `fix_velocity`, removes the outward velocity along each limit it hit. In parallel over
  /// particles; deterministic.
  void apply(const ClothModel& model, ClothState& state, bool fix_velocity) const;
  /// Projects one position xp of free particle p onto its limits (pins at x), in the same order.
  void project(const ClothModel& model, const std::vector<Vec3>& x, int32_t p, Vec3& xp) const {
    for (const int32_t a : pins_) project_attachment(x[a], limit(model, p, a), xp);
  }
  /// Whether position xp of free particle p lies beyond, or within `reach` of, one of its limits
  /// (pins at x).
  bool within_reach(const ClothModel& model, const std::vector<Vec3>& x, int32_t p, const Vec3& xp,
                    double reach) const {
    for (const int32_t a : pins_)
      if ((xp - x[a]).norm() > limit(model, p, a) - reach) return true;
    return false;
  }
  /// The pinned particles, in order.
  const std::vector<int32_t>& pins() const { return pins_; }
  /// The largest distance allowed between particle p and pin a, m.
  double limit(const ClothModel& model, int32_t p, int32_t a) const {
    // The rest distance along a flat grid is the straight line between rest positions (the
    // geodesic of a flat rectangle), so it is computed here rather than stored per pair.
    return scale_ * (model.rest_position[p] - model.rest_position[a]).norm();
  }

 private:
  std::vector<int32_t> pins_;
  double scale_ = 1.0;  ///< 1 + slack
};

}  // namespace drape
