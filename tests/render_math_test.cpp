// The viewer's camera, ray and picking math, against results worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "drape/collider.h"
#include "drape/scene.h"
#include "render/camera.h"
#include "render/picking.h"

namespace drape::render {
namespace {

constexpr double kTol = 1e-9;

// Eye at (0, 0, 5) looking toward −z at the origin, 45° vertical field of view.
OrbitCamera front_camera() {
  OrbitCamera c;
  c.target = {0.0, 0.0, 0.0};
  c.yaw = 0.0;
  c.pitch = 0.0;
  c.distance = 5.0;
  return c;
}

void expect_near(const Vec3& a, const Vec3& b, double tol = kTol) {
  EXPECT_NEAR((a - b).norm(), 0.0, tol) << "got " << a.transpose() << ", want " << b.transpose();
}

TEST(RenderCamera, RayThroughTheCentreAndEdgesOfAKnownView) {
  const OrbitCamera cam = front_camera();
  const Viewport vp{0.0, 0.0, 200.0, 100.0};
  const glm::dmat4 view = cam.view(), proj = cam.projection(vp.aspect());
  const double t = std::tan(0.5 * cam.fov_y);

  const Ray centre = ray_from_pixel(view, proj, vp, 100.0, 50.0);
  expect_near(centre.origin, Vec3(0, 0, 5));
  expect_near(centre.direction, Vec3(0, 0, -1));
  // The right edge's middle: the horizontal half-angle is atan(aspect · tan(fov_y / 2)).
  expect_near(ray_from_pixel(view, proj, vp, 200.0, 50.0).direction,
              Vec3(2.0 * t, 0, -1).normalized());
  // The top edge's middle: window y grows downward, the world's y upward.
  expect_near(ray_from_pixel(view, proj, vp, 100.0, 0.0).direction, Vec3(0, t, -1).normalized());
  // A viewport that starts 50 units from the window's left edge shifts the pixels with it.
  const Viewport shifted{50.0, 0.0, 200.0, 100.0};
  expect_near(ray_from_pixel(view, proj, shifted, 150.0, 50.0).direction, Vec3(0, 0, -1));
}

TEST(RenderCamera, ProjectionInvertsTheRay) {
  OrbitCamera cam = front_camera();
  cam.yaw = 0.7;
  cam.pitch = -0.4;
  cam.target = {0.3, 1.2, -0.5};
  const Viewport vp{10.0, 20.0, 640.0, 480.0};
  const glm::dmat4 view = cam.view(), proj = cam.projection(vp.aspect());
  for (const auto& [px, py] : {std::pair{13.0, 400.0}, {300.5, 21.0}, {649.0, 499.0}}) {
    const Ray r = ray_from_pixel(view, proj, vp, px, py);
    expect_near(r.origin, Vec3(cam.eye().x, cam.eye().y, cam.eye().z));
    EXPECT_NEAR(r.direction.norm(), 1.0, kTol);
    for (double d : {0.5, 3.0, 40.0}) {
      const glm::dvec2 p = project_to_pixel(view, proj, vp, r.at(d));
      EXPECT_NEAR(p.x, px, 1e-6);
      EXPECT_NEAR(p.y, py, 1e-6);
    }
  }
}

TEST(RenderCamera, OrbitCirclesTheTargetAndClampsThePitch) {
  OrbitCamera cam = front_camera();
  cam.target = {1.0, 2.0, 3.0};
  cam.orbit(M_PI / 2, 0.0);  // a quarter turn: the eye moves from +z to +x of the target
  const glm::dvec3 e = cam.eye();
  EXPECT_NEAR(e.x, 6.0, kTol);
  EXPECT_NEAR(e.y, 2.0, kTol);
  EXPECT_NEAR(e.z, 3.0, kTol);
  cam.orbit(0.0, M_PI / 6);  // 30° up
  EXPECT_NEAR(cam.eye().y, 2.0 + 5.0 * std::sin(M_PI / 6), kTol);
  EXPECT_NEAR(glm::length(cam.eye() - cam.target), 5.0, kTol);
  // The view matrix puts the target straight ahead at the camera's distance.
  const glm::dvec4 t = cam.view() * glm::dvec4(cam.target, 1.0);
  EXPECT_NEAR(t.x, 0.0, kTol);
  EXPECT_NEAR(t.y, 0.0, kTol);
  EXPECT_NEAR(t.z, -5.0, kTol);
  cam.orbit(0.0, 10.0);  // far past straight up
  EXPECT_NEAR(cam.pitch, 89.0 * M_PI / 180.0, 1e-12);
  EXPECT_TRUE(std::isfinite(cam.view()[0][0]));
  cam.orbit(0.0, -20.0);
  EXPECT_NEAR(cam.pitch, -89.0 * M_PI / 180.0, 1e-12);
}

TEST(RenderCamera, ZoomScalesTheDistanceAndKeepsTheTarget) {
  OrbitCamera cam = front_camera();
  cam.zoom(1.0);
  EXPECT_NEAR(cam.distance, 4.5, kTol);
  cam.zoom(-2.0);
  EXPECT_NEAR(cam.distance, 5.0 / 0.9, kTol);
  EXPECT_NEAR(glm::length(cam.eye() - cam.target), cam.distance, kTol);
  EXPECT_NEAR(glm::length(cam.target), 0.0, kTol);
  // A point twice as far away in the view looks half as large: zoom changes the picture.
  const Viewport vp{0.0, 0.0, 100.0, 100.0};
  const Vec3 p(0.5, 0.0, 0.0);
  const double before = project_to_pixel(cam.view(), cam.projection(1.0), vp, p).x - 50.0;
  cam.distance *= 2.0;
  const double after = project_to_pixel(cam.view(), cam.projection(1.0), vp, p).x - 50.0;
  EXPECT_NEAR(after, 0.5 * before, 1e-9);
}

TEST(RenderCamera, PanMakesTheSceneFollowTheCursor) {
  OrbitCamera cam = front_camera();
  cam.yaw = 0.3;
  cam.pitch = 0.2;
  const Viewport vp{0.0, 0.0, 400.0, 300.0};
  const Vec3 old_target(cam.target.x, cam.target.y, cam.target.z);
  cam.pan(30.0, -12.0, vp.height);
  const glm::dvec2 p = project_to_pixel(cam.view(), cam.projection(vp.aspect()), vp, old_target);
  EXPECT_NEAR(p.x, 200.0 + 30.0, 1e-9);
  EXPECT_NEAR(p.y, 150.0 - 12.0, 1e-9);
}

TEST(RenderCamera, FrameCentresTheBoxAndFitsItsRadius) {
  OrbitCamera cam = front_camera();
  const Vec3 lo(-1.0, 0.0, -0.5), hi(3.0, 2.0, 0.5);
  const Viewport vp{0.0, 0.0, 300.0, 200.0};  // wide: the height is the narrower field
  cam.frame(lo, hi, vp.aspect());
  const glm::dmat4 view = cam.view(), proj = cam.projection(vp.aspect());
  const glm::dvec2 c = project_to_pixel(view, proj, vp, Vec3(1.0, 1.0, 0.0));
  EXPECT_NEAR(c.x, 150.0, 1e-9);
  EXPECT_NEAR(c.y, 100.0, 1e-9);
  // The bounding radius straight up from the target, at its depth, reaches the top edge.
  const double r = 0.5 * (hi - lo).norm();
  EXPECT_NEAR(project_to_pixel(view, proj, vp, Vec3(1.0, 1.0 + r, 0.0)).y, 0.0, 1e-9);
}

TEST(RenderCamera, FitShowsEveryCornerOfTheBoxFromAnyAngle) {
  // frame() fits the bounding radius at the target's depth; seen from above and aside in a
  // wide view, a near corner can still fall outside, which fit() must not allow.
  const Vec3 lo(-1.0, -0.2, -1.0), hi(1.0, 2.0, 3.0);
  for (const double aspect : {0.5, 1.0, 920.0 / 720.0, 3.0}) {
    for (const double yaw : {0.0, 0.45, 1.2, 2.5}) {
      for (const double pitch : {-0.6, 0.0, 0.3, 1.2}) {
        OrbitCamera cam;
        cam.yaw = yaw;
        cam.pitch = pitch;
        cam.fit(lo, hi, aspect, 0.9);
        EXPECT_TRUE(cam.shows(lo, hi, aspect, 0.9)) << aspect << " " << yaw << " " << pitch;
      }
    }
  }
  // A box behind the eye, or beside the view, is not shown.
  OrbitCamera cam = front_camera();
  const glm::dvec3 eye = cam.eye();
  const Vec3 behind(eye.x, eye.y, eye.z + 1.0);
  EXPECT_FALSE(cam.shows(behind, behind + Vec3::Constant(0.1), 1.0, 1.0));
  EXPECT_FALSE(cam.shows(Vec3(50.0, 0.0, 0.0), Vec3(51.0, 1.0, 1.0), 1.0, 1.0));
}

TEST(RenderPicking, PicksThePointClosestToTheRay) {
  std::vector<Vec3> points;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) points.emplace_back(0.1 * i, 0.1 * j, 0.0);
  Ray ray;
  ray.origin = Vec3(0.21, 0.29, 4.0);
  ray.direction = Vec3(0.0, 0.0, -1.0);
  const Pick p = nearest_to_ray(ray, points, 0.05);
  ASSERT_TRUE(p);
  EXPECT_EQ(p.index, 2 * 5 + 3);  // (0.2, 0.3)
  EXPECT_NEAR(p.along, 4.0, kTol);
  EXPECT_NEAR(p.distance, std::hypot(0.01, 0.01), kTol);
}

TEST(RenderPicking, NothingWhenTheCursorIsFarFromTheCloth) {
  const std::vector<Vec3> points{{0, 0, 0}, {1, 0, 0}};
  Ray ray;
  ray.origin = Vec3(0.5, 2.0, 4.0);
  ray.direction = Vec3(0.0, 0.0, -1.0);
  // 2 m off the ray at 4 m: outside a cone of slope 0.1 (0.4 m there).
  EXPECT_FALSE(nearest_to_ray(ray, points, 0.1));
  // The same offset inside a wide cone is picked.
  EXPECT_TRUE(nearest_to_ray(ray, points, 1.0));
}

TEST(RenderPicking, IgnoresPointsBehindTheEyeAndNonFinitePoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec3> points{{0, 0, 5}, {nan, 0, 0}, {0.05, 0, 0}};
  Ray ray;
  ray.origin = Vec3(0.0, 0.0, 4.0);
  ray.direction = Vec3(0.0, 0.0, -1.0);
  const Pick p = nearest_to_ray(ray, points, 0.1);
  ASSERT_TRUE(p);
  EXPECT_EQ(p.index, 2);
}

TEST(RenderPicking, EqualDistancesGoToThePointNearerTheEye) {
  const std::vector<Vec3> points{{0.01, 0, -1}, {0.01, 0, 1}};
  Ray ray;
  ray.origin = Vec3(0.0, 0.0, 4.0);
  ray.direction = Vec3(0.0, 0.0, -1.0);
  EXPECT_EQ(nearest_to_ray(ray, points, 0.1).index, 1);
}

TEST(RenderPicking, PickRadiusIsInPixelsAtAnyDepth) {
  const OrbitCamera cam = front_camera();
  const Viewport vp{0.0, 0.0, 400.0, 300.0};
  const glm::dmat4 view = cam.view(), proj = cam.projection(vp.aspect());
  const double slope = pick_slope(10.0, vp.height, cam.fov_y);
  const Ray ray = ray_from_pixel(view, proj, vp, 200.0, 150.0);
  for (double depth : {1.0, 4.0, 30.0}) {
    // Points 8 and 12 pixels right of the cursor, at this depth.
    const Vec3 near8 = ray_from_pixel(view, proj, vp, 208.0, 150.0).at(depth);
    const Vec3 far12 = ray_from_pixel(view, proj, vp, 212.0, 150.0).at(depth);
    EXPECT_TRUE(nearest_to_ray(ray, std::vector<Vec3>{near8}, slope)) << depth;
    EXPECT_FALSE(nearest_to_ray(ray, std::vector<Vec3>{far12}, slope)) << depth;
  }
}

TEST(RenderPicking, DragKeepsTheDistanceAlongTheRay) {
  OrbitCamera cam = front_camera();
  cam.yaw = -0.5;
  cam.pitch = 0.25;
  const Viewport vp{0.0, 0.0, 800.0, 600.0};
  const glm::dmat4 view = cam.view(), proj = cam.projection(vp.aspect());
  const std::vector<Vec3> points{{0.2, -0.1, 0.3}, {-0.4, 0.3, 0.0}};
  // Press on the first point's pixel, then move the cursor 120 px right and 45 px up.
  const glm::dvec2 press = project_to_pixel(view, proj, vp, points[0]);
  const Ray down = ray_from_pixel(view, proj, vp, press.x, press.y);
  const Pick pick = nearest_to_ray(down, points, pick_slope(8.0, vp.height, cam.fov_y));
  ASSERT_EQ(pick.index, 0);
  const double d = (points[0] - down.origin).norm();
  EXPECT_NEAR(pick.along, d, 1e-9);  // the press ray passes through the point
  const Ray moved = ray_from_pixel(view, proj, vp, press.x + 120.0, press.y - 45.0);
  const Vec3 target = drag_target(moved, pick.along);
  EXPECT_NEAR((target - moved.origin).norm(), d, 1e-9);  // same distance from the eye
  const glm::dvec2 seen = project_to_pixel(view, proj, vp, target);
  EXPECT_NEAR(seen.x, press.x + 120.0, 1e-6);  // under the cursor
  EXPECT_NEAR(seen.y, press.y - 45.0, 1e-6);
}

// Shift-drag's pick: the first collider surface along the ray (sphere tracing), planes left out.
TEST(RenderPicking, TheFirstColliderAlongTheRayIsPickedAtItsSurface) {
  ColliderDef ground, ball, box;
  ground.type = ColliderType::plane;
  ground.center = Vec3(0.0, -1.0, 0.0);
  ball.center = Vec3(0.0, 0.0, -5.0);
  ball.radius = 1.0;
  box.type = ColliderType::box;
  box.center = Vec3(0.0, 0.0, -10.0);
  box.half_extents = Vec3(2.0, 2.0, 0.5);
  const std::vector<Collider> colliders = make_colliders({ground, box, ball});
  const render::Ray ahead{Vec3::Zero(), -Vec3::UnitZ()};
  const render::Pick hit = render::first_collider_hit(ahead, colliders);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit.index, 2);  // the ball, in front of the box
  EXPECT_NEAR(hit.along, 4.0, 1e-3);
  // Past the ball's side, the box's face at z = −9.5.
  const render::Pick beside =
      render::first_collider_hit({Vec3(1.5, 0.0, 0.0), -Vec3::UnitZ()}, colliders);
  ASSERT_TRUE(beside);
  EXPECT_EQ(beside.index, 1);
  EXPECT_NEAR(beside.along, 9.5, 1e-3);
  // Down at the ground only: nothing (a plane is not carried).
  EXPECT_FALSE(render::first_collider_hit({Vec3(5.0, 0.0, 0.0), -Vec3::UnitY()}, colliders));
  EXPECT_FALSE(render::first_collider_hit({Vec3::Zero(), Vec3::UnitZ()}, colliders));
}

TEST(RenderPicking, HandVelocityIsTheTargetsMotionOverAFrame) {
  HandTracker hand;
  hand.start(Vec3(1.0, 2.0, 3.0));
  hand.move(Vec3(1.5, 2.0, 3.0));
  hand.move(Vec3(1.1, 2.0, 2.9));  // only where the cursor is at the frame's end counts
  hand.frame_done(0.1);
  expect_near(hand.velocity(), Vec3(1.0, 0.0, -1.0));
  hand.frame_done(0.1);  // the hand stopped
  expect_near(hand.velocity(), Vec3::Zero());
}

}  // namespace
}  // namespace drape::render
