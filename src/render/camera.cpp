#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace drape::render {

namespace {
constexpr double kPitchLimit = 1.5533430342749532;  // 89°
}

glm::dvec3 OrbitCamera::eye() const {
  const double c = std::cos(pitch);
  return target + distance * glm::dvec3(c * std::sin(yaw), std::sin(pitch), c * std::cos(yaw));
}

glm::dmat4 OrbitCamera::view() const {
  return glm::lookAt(eye(), target, glm::dvec3(0.0, 1.0, 0.0));
}

glm::dmat4 OrbitCamera::projection(double aspect) const {
  // A depth range proportional to the distance keeps depth precision where the scene is.
  return glm::perspective(fov_y, aspect, 0.01 * distance, 100.0 * distance);
}

void OrbitCamera::orbit(double dyaw, double dpitch) {
  yaw = std::remainder(yaw + dyaw, 2.0 * M_PI);
  pitch = std::clamp(pitch + dpitch, -kPitchLimit, kPitchLimit);
}

void OrbitCamera::pan(double dx, double dy, double viewport_height) {
  // One window unit at the target's depth spans this many metres.
  const double scale = 2.0 * distance * std::tan(0.5 * fov_y) / viewport_height;
  const glm::dmat4 v = view();
  const glm::dvec3 right(v[0][0], v[1][0], v[2][0]);
  const glm::dvec3 up(v[0][1], v[1][1], v[2][1]);
  target += scale * (-dx * right + dy * up);
}

void OrbitCamera::zoom(double steps) {
  distance = std::clamp(distance * std::pow(0.9, steps), 0.05, 1e4);
}

void OrbitCamera::frame(const Vec3& lo, const Vec3& hi, double aspect) {
  const Vec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-3);
  target = glm::dvec3(centre.x(), centre.y(), centre.z());
  // The sphere must fit the narrower of the two fields of view.
  const double half_y = 0.5 * fov_y;
  const double half_x = std::atan(std::tan(half_y) * aspect);
  // The sphere around a box is loose (the box fills about half of it), so fitting the sphere's
  // silhouette (radius / sin) would leave the box small; fitting its radius at the target's
  // depth (radius / tan) frames the box snugly without cutting into it in practice.
  distance = radius / std::tan(std::min(half_x, half_y));
}

bool OrbitCamera::shows(const Vec3& lo, const Vec3& hi, double aspect, double fraction) const {
  const glm::dmat4 clip_from_world = projection(aspect) * view();
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec4 c =
        clip_from_world * glm::dvec4(corner & 1 ? hi.x() : lo.x(), corner & 2 ? hi.y() : lo.y(),
                                     corner & 4 ? hi.z() : lo.z(), 1.0);
    if (!(c.w > 0.0) || std::abs(c.x) > fraction * c.w || std::abs(c.y) > fraction * c.w)
      return false;
  }
  return true;
}

void OrbitCamera::fit(const Vec3& lo, const Vec3& hi, double aspect, double fraction) {
  frame(lo, hi, aspect);
  // Each step backs off 10%; 60 of them are 300 times as far, more than any box needs.
  for (int step = 0; step < 60 && !shows(lo, hi, aspect, fraction); ++step) distance *= 1.1;
}

bool scene_bounds(const std::vector<Vec3>& x, const std::vector<Collider>& colliders, Vec3& lo,
                  Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& p : x) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (const Collider& c : colliders) {
    if (c.type == ColliderType::plane || !std::isfinite(c.bound_radius)) continue;
    lo = lo.cwiseMin(c.bound_center - Vec3::Constant(c.bound_radius));
    hi = hi.cwiseMax(c.bound_center + Vec3::Constant(c.bound_radius));
  }
  return (lo.array() <= hi.array()).all();
}

OrbitCamera default_camera(const std::vector<Vec3>& x, const std::vector<Collider>& colliders,
                           double aspect) {
  OrbitCamera camera;
  camera.yaw = 0.45;
  camera.pitch = 0.3;
  Vec3 lo, hi;
  if (!scene_bounds(x, colliders, lo, hi)) return camera;
  // Room for the cloth to sag and swing: a twentieth of the box on every side.
  const Vec3 margin = Vec3::Constant(0.05 * (hi - lo).maxCoeff());
  camera.frame(lo - margin, hi + margin, aspect);
  return camera;
}

Ray ray_from_pixel(const glm::dmat4& view, const glm::dmat4& projection, const Viewport& viewport,
                   double px, double py) {
  const double nx = 2.0 * (px - viewport.x) / viewport.width - 1.0;
  const double ny = 1.0 - 2.0 * (py - viewport.y) / viewport.height;
  const glm::dmat4 inv = glm::inverse(projection * view);
  const glm::dvec4 n = inv * glm::dvec4(nx, ny, -1.0, 1.0);
  const glm::dvec4 f = inv * glm::dvec4(nx, ny, 1.0, 1.0);
  const glm::dvec3 near_point = glm::dvec3(n) / n.w;
  const glm::dvec3 far_point = glm::dvec3(f) / f.w;
  // The ray starts at the eye (the view matrix's origin), not on the near plane, so distances
  // along it are distances from the eye.
  const glm::dvec3 eye = glm::dvec3(glm::inverse(view)[3]);
  const glm::dvec3 dir = glm::normalize(far_point - near_point);
  Ray r;
  r.origin = Vec3(eye.x, eye.y, eye.z);
  r.direction = Vec3(dir.x, dir.y, dir.z);
  return r;
}

glm::dvec2 project_to_pixel(const glm::dmat4& view, const glm::dmat4& projection,
                            const Viewport& viewport, const Vec3& point) {
  const glm::dvec4 c = projection * view * glm::dvec4(point.x(), point.y(), point.z(), 1.0);
  const double nx = c.x / c.w, ny = c.y / c.w;
  return {viewport.x + 0.5 * (nx + 1.0) * viewport.width,
          viewport.y + 0.5 * (1.0 - ny) * viewport.height};
}

}  // namespace drape::render
