// Picking and dragging particles with the camera ray (the seed's mouse drag): plain functions
// over positions, no OpenGL, unit-tested.
#pragma once

#include <cstdint>
#include <span>

#include "drape/collider.h"
#include "drape/math.h"
#include "render/camera.h"

namespace drape::render {

/// The particle a ray picked.
struct Pick {
  int32_t index = -1;     ///< particle index; −1 when nothing lies within the pick cone
  double along = 0.0;     ///< m, distance d of the particle's foot point along the ray
  double distance = 0.0;  ///< m, the particle's distance from the ray
  explicit operator bool() const { return index >= 0; }
};

/// The point closest to the ray among those in front of its origin and inside the cone of
/// half-angle atan(`slope`) around it (so the pick radius is the same number of pixels near and
/// far). Ties go to the point nearer the eye. Non-finite points are skipped.
Pick nearest_to_ray(const Ray& ray, std::span<const Vec3> points, double slope);

/// The cone slope that makes the pick radius `pixels` wide in a viewport `viewport_height`
/// window units tall seen with vertical field of view `fov_y` (rad).
double pick_slope(double pixels, double viewport_height, double fov_y);

/// The first collider a ray meets (not a plane: it has no place to be carried to), by sphere
/// tracing each one's signed distance: index −1 when it meets none within `far` (m). `along` is
/// the hit's distance along the ray.
Pick first_collider_hit(const Ray& ray, std::span<const Collider> colliders, double far = 100.0);

/// Where a held particle goes: the point at the picked distance along the current ray.
inline Vec3 drag_target(const Ray& ray, double along) {
  return ray.at(along);
}

/// The hand's velocity while dragging: the target's displacement over each simulated frame.
class HandTracker {
 public:
  /// Starts tracking at `target` (the picked particle's position on the ray).
  void start(const Vec3& target);
  /// The cursor moved the target.
  void move(const Vec3& target) { target_ = target; }
  /// A frame of `dt` seconds was simulated; the velocity becomes the target's motion over it.
  void frame_done(double dt);
  const Vec3& target() const { return target_; }
  /// m/s, over the last simulated frame.
  const Vec3& velocity() const { return velocity_; }

 private:
  Vec3 target_ = Vec3::Zero();
  Vec3 last_frame_target_ = Vec3::Zero();
  Vec3 velocity_ = Vec3::Zero();
};

}  // namespace drape::render
