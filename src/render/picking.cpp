#include "render/picking.h"

#include <cmath>
#include <limits>

namespace drape::render {

Pick nearest_to_ray(const Ray& ray, std::span<const Vec3> points, double slope) {
  Pick best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    if (!p.allFinite()) continue;
    const Vec3 rel = p - ray.origin;
    const double t = rel.dot(ray.direction);
    if (t <= 0.0) continue;
    const double dist = (rel - t * ray.direction).norm();
    if (dist > slope * t) continue;
    if (dist < best_distance || (dist == best_distance && t < best.along)) {
      best_distance = dist;
      best.index = static_cast<int32_t>(i);
      best.along = t;
      best.distance = dist;
    }
  }
  return best;
}

double pick_slope(double pixels, double viewport_height, double fov_y) {
  return 2.0 * std::tan(0.5 * fov_y) * pixels / viewport_height;
}

void HandTracker::start(const Vec3& target) {
  target_ = last_frame_target_ = target;
  velocity_.setZero();
}

void HandTracker::frame_done(double dt) {
  velocity_ = (target_ - last_frame_target_) / dt;
  last_frame_target_ = target_;
}

}  // namespace drape::render
