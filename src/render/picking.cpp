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

Pick first_collider_hit(const Ray& ray, std::span<const Collider> colliders, double far) {
  constexpr double kSurface = 1e-4;  // m: this close counts as a hit
  constexpr int kMarches = 512;
  Pick best;
  best.along = far;
  for (size_t k = 0; k < colliders.size(); ++k) {
    const Collider& c = colliders[k];
    if (c.type == ColliderType::plane) continue;
    // Each step goes as far as the distance to the surface: it cannot pass through it.
    double t = 0.0;
    Vec3 n;
    for (int i = 0; i < kMarches && t < best.along; ++i) {
      const double d = signed_distance(c, ray.at(t), n);
      if (!std::isfinite(d)) break;
      if (std::abs(d) < kSurface) {
        best = {static_cast<int32_t>(k), t, 0.0};
        break;
      }
      if (d < 0.0 && t == 0.0) break;  // the eye is inside it: not something to pick
      t += std::abs(d);
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
