// The viewer's orbit camera and the ray through a pixel: plain math, no OpenGL, unit-tested.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "drape/cloth.h"
#include "drape/collider.h"
#include "drape/math.h"

namespace drape::render {

/// A rectangle of the window in window coordinates: origin at the top-left, y down, in the
/// units the windowing system reports cursor positions in.
struct Viewport {
  double x = 0.0;       ///< left edge
  double y = 0.0;       ///< top edge
  double width = 1.0;   ///< > 0
  double height = 1.0;  ///< > 0
  double aspect() const { return width / height; }
};

/// A half-line origin + t·direction, t >= 0; direction has unit length.
struct Ray {
  Vec3 origin = Vec3::Zero();      ///< m
  Vec3 direction = Vec3::UnitZ();  ///< unit
  Vec3 at(double t) const { return origin + t * direction; }
};

/// A camera that circles a target point: yaw turns it around the world's +y axis, pitch raises
/// it above the target's horizontal plane. Angles in radians.
struct OrbitCamera {
  glm::dvec3 target{0.0, 1.0, 0.0};   ///< m, the point looked at and orbited
  double yaw = 0.0;                   ///< rad; 0 puts the eye on the +z side looking toward −z
  double pitch = 0.0;                 ///< rad, in (−π/2, π/2); positive looks down from above
  double distance = 5.0;              ///< m, eye to target, > 0
  double fov_y = 0.7853981633974483;  ///< rad, vertical field of view (45°)

  glm::dvec3 eye() const;
  glm::dmat4 view() const;
  /// Near and far planes follow the distance so zooming never clips the scene.
  glm::dmat4 projection(double aspect) const;

  /// Turns the camera by the given angles; pitch stays 1° short of straight up or down.
  void orbit(double dyaw, double dpitch);
  /// Moves the target in the view plane so the point at the target's depth follows the cursor:
  /// (dx, dy) window units of cursor motion in a viewport `viewport_height` tall.
  void pan(double dx, double dy, double viewport_height);
  /// Scroll `steps` notches: each one brings the eye 10% closer (negative: farther).
  void zoom(double steps);
  /// Aims at the centre of the box [lo, hi] from the distance at which the box's bounding radius,
  /// at the target's depth, spans half the narrower side of a viewport of the given aspect
  /// ratio; keeps the current angles.
  void frame(const Vec3& lo, const Vec3& hi, double aspect);
  /// Whether every corner of the box [lo, hi] is in front of the eye and inside the middle
  /// `fraction` (0 to 1) of the view's width and height, for a viewport of the given aspect.
  bool shows(const Vec3& lo, const Vec3& hi, double aspect, double fraction) const;
  /// frame(), then the eye moved back until shows(lo, hi, aspect, fraction): frame() fits the
  /// box's bounding radius at the target's depth, which a near corner seen in perspective can
  /// still pass.
  void fit(const Vec3& lo, const Vec3& hi, double aspect, double fraction);
};

/// The box holding the cloth's finite positions and the spheres (planes have no bounds).
/// Returns false when there is nothing finite to hold.
bool scene_bounds(const std::vector<Vec3>& x, const std::vector<Collider>& colliders, Vec3& lo,
                  Vec3& hi);

/// The viewer's start view: a little from the right and above, framing the cloth and the
/// spheres with some room around them.
OrbitCamera default_camera(const std::vector<Vec3>& x, const std::vector<Collider>& colliders,
                           double aspect);

/// The ray from the eye through window point (px, py) of `viewport`, for a camera with these
/// view and projection matrices. Pixel centres lie at half-integers.
Ray ray_from_pixel(const glm::dmat4& view, const glm::dmat4& projection, const Viewport& viewport,
                   double px, double py);

/// Where `point` appears in `viewport`, in window units (the inverse of ray_from_pixel).
glm::dvec2 project_to_pixel(const glm::dmat4& view, const glm::dmat4& projection,
                            const Viewport& viewport, const Vec3& point);

}  // namespace drape::render
