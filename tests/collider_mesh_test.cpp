// Colliders as meshes for the exports: on the surface, facing out, no degenerate triangles.
#include <gtest/gtest.h>

#include "io/collider_mesh.h"

namespace {

using drape::Collider;
using drape::ColliderType;
using drape::Vec3;
using drape::io::collider_mesh;
using drape::io::SurfaceMesh;

// Every triangle has area and winds counter-clockwise seen from the side its normals face.
void expect_facing_out(const SurfaceMesh& m) {
  for (const auto& t : m.triangles) {
    for (int32_t v : t) ASSERT_LT(v, static_cast<int32_t>(m.position.size()));
    const Vec3 face =
        (m.position[t[1]] - m.position[t[0]]).cross(m.position[t[2]] - m.position[t[0]]);
    EXPECT_GT(face.norm(), 1e-6);
    EXPECT_GT(face.dot(m.normal[t[0]] + m.normal[t[1]] + m.normal[t[2]]), 0.0);
  }
}

TEST(ColliderMesh, ASphereIsAUvSphereOnItsSurfaceFacingOut) {
  Collider c;
  c.type = ColliderType::sphere;
  c.center = Vec3(0.3, 0.4, 0.2);
  c.radius = 0.4;
  const SurfaceMesh m = collider_mesh(c, Vec3::Zero(), 10.0, 16, 8);
  ASSERT_EQ(m.position.size(), 2u + 7u * 16u);   // two poles, seven rings between
  EXPECT_EQ(m.triangles.size(), 2u * 16u * 7u);  // a fan at each pole, quads between
  for (size_t i = 0; i < m.position.size(); ++i) {
    EXPECT_NEAR((m.position[i] - c.center).norm(), c.radius, 1e-12);
    EXPECT_NEAR(m.normal[i].norm(), 1.0, 1e-12);
    EXPECT_NEAR(m.normal[i].dot((m.position[i] - c.center) / c.radius), 1.0, 1e-12);
  }
  expect_facing_out(m);
}

TEST(ColliderMesh, APlaneIsASquareAroundTheClothOnItsSideOfThePlane) {
  Collider c;
  c.type = ColliderType::plane;
  c.center = Vec3(0.0, -1.0, 0.0);
  c.normal = Vec3(0.0, 1.0, 1.0).normalized();
  const Vec3 focus(0.5, 2.0, -0.5);
  const SurfaceMesh m = collider_mesh(c, focus, 20.0);
  ASSERT_EQ(m.position.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 2u);
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : m.position) {
    EXPECT_NEAR(c.normal.dot(p - c.center), 0.0, 1e-12);  // on the plane
    centre += p / 4.0;
  }
  // Centred below the focus, along the normal, with sides of 20 m.
  EXPECT_NEAR((centre - focus).cross(c.normal).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.position[1] - m.position[0]).norm(), 20.0, 1e-12);
  EXPECT_NEAR((m.position[2] - m.position[1]).norm(), 20.0, 1e-12);
  expect_facing_out(m);
}

}  // namespace
