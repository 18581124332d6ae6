#include "io/collider_mesh.h"

#include <cmath>
#include <numbers>

namespace drape::io {

namespace {

SurfaceMesh sphere(const Collider& c, int segments, int rings) {
  SurfaceMesh m;
  // The poles once each, the rings between them with `segments` vertices each.
  m.normal.push_back(Vec3::UnitY());
  for (int r = 1; r < rings; ++r) {
    const double theta = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / segments;
      m.normal.emplace_back(std::sin(theta) * std::sin(phi), std::cos(theta),
                            std::sin(theta) * std::cos(phi));
    }
  }
  m.normal.push_back(-Vec3::UnitY());
  for (const Vec3& n : m.normal) m.position.push_back(c.center + c.radius * n);

  const int32_t south = static_cast<int32_t>(m.normal.size()) - 1;
  auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      const int32_t a = ring(r, s), b = ring(r, s + 1), d = ring(r + 1, s), e = ring(r + 1, s + 1);
      m.triangles.push_back({a, d, e});
      m.triangles.push_back({a, e, b});
    }
    m.triangles.push_back({ring(rings - 1, s), south, ring(rings - 1, s + 1)});
  }
  return m;
}

SurfaceMesh plane(const Collider& c, const Vec3& focus, double extent) {
  SurfaceMesh m;
  const Vec3 n = c.normal.normalized();
  const Vec3 centre = focus - n.dot(focus - c.center) * n;
  // Two directions in the plane, u × w = n, so the square winds counter-clockwise seen from n.
  const Vec3 u = n.unitOrthogonal();
  const Vec3 w = n.cross(u);
  const double h = 0.5 * extent;
  for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    m.position.push_back(centre + h * (a * u + b * w));
    m.normal.push_back(n);
  }
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace

SurfaceMesh collider_mesh(const Collider& c, const Vec3& focus, double extent, int segments,
                          int rings) {
  return c.type == ColliderType::sphere ? sphere(c, segments, rings) : plane(c, focus, extent);
}

}  // namespace drape::io
