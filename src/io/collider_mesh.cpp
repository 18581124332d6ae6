#include "io/collider_mesh.h"

#include <cmath>
#include <numbers>

#include "core/collision/triangle_shape.h"

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

// A capsule: a sphere's rings split at its equator, the upper half around b and the lower
// around a (the equator ring twice: the strip between the copies is the cylinder), each pole a
// fan, turned from y onto the axis a → b.
SurfaceMesh capsule(const Collider& c, int segments, int rings) {
  SurfaceMesh m;
  const int half = std::max(1, rings / 2);
  const Vec3 axis = c.b - c.a;
  // A frame whose y is the axis (any frame for a = b).
  Mat3 R = Mat3::Identity();
  if (axis.squaredNorm() > 0.0) {
    const Vec3 y = axis.normalized(), x = y.unitOrthogonal();
    R << x, y, x.cross(y);
  }
  auto add = [&](const Vec3& local, const Vec3& end) {
    m.normal.push_back(R * local);
    m.position.push_back(end + c.radius * m.normal.back());
  };
  add(Vec3::UnitY(), c.b);
  // Rows 1..half around b (the last on the equator), then half..2·half−1 around a.
  for (int row = 1; row <= 2 * half; ++row) {
    const int r = row <= half ? row : row - 1;
    const double theta = std::numbers::pi * r / (2 * half);
    for (int k = 0; k < segments; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / segments;
      add(Vec3(std::sin(theta) * std::sin(phi), std::cos(theta), std::sin(theta) * std::cos(phi)),
          row <= half ? c.b : c.a);
    }
  }
  add(-Vec3::UnitY(), c.a);
  const int rows = 2 * half;
  const int32_t south = static_cast<int32_t>(m.position.size()) - 1;
  auto at = [&](int row, int k) { return 1 + (row - 1) * segments + (k % segments); };
  for (int k = 0; k < segments; ++k) {
    m.triangles.push_back({0, at(1, k), at(1, k + 1)});
    for (int row = 1; row < rows; ++row) {
      const int32_t a = at(row, k), b = at(row, k + 1), d = at(row + 1, k), e = at(row + 1, k + 1);
      m.triangles.push_back({a, d, e});
      m.triangles.push_back({a, e, b});
    }
    m.triangles.push_back({at(rows, k), south, at(rows, k + 1)});
  }
  return m;
}

// A box: four vertices per face (flat normals), two triangles each.
SurfaceMesh box(const Collider& c) {
  SurfaceMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (const double side : {-1.0, 1.0}) {
      Vec3 n = Vec3::Zero();
      n[axis] = side;
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const int32_t first = static_cast<int32_t>(m.position.size());
      for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        Vec3 p = n.cwiseProduct(c.half_extents);
        p[u] = a * c.half_extents[u];
        p[w] = b * c.half_extents[w];
        m.position.push_back(c.center + c.rotation * p);
        m.normal.push_back(c.rotation * n);
      }
      // Counter-clockwise seen from outside: u × w = the axis, so flip on the negative side.
      if (side > 0) {
        m.triangles.push_back({first, first + 1, first + 2});
        m.triangles.push_back({first, first + 2, first + 3});
      } else {
        m.triangles.push_back({first, first + 2, first + 1});
        m.triangles.push_back({first, first + 3, first + 2});
      }
    }
  return m;
}

}  // namespace

SurfaceMesh triangle_mesh(const Collider& c, bool posed) {
  SurfaceMesh m;
  if (!c.mesh) return m;
  const Pose identity;
  const Pose& pose = posed ? c.pose : identity;
  for (const Vec3& v : c.mesh->vertices()) m.position.push_back(pose.apply(v));
  m.normal.assign(m.position.size(), Vec3::Zero());
  for (const Triangle& t : c.mesh->triangles()) {
    m.triangles.push_back(t);
    const Vec3 n = (m.position[t[1]] - m.position[t[0]]).cross(m.position[t[2]] - m.position[t[0]]);
    for (int k = 0; k < 3; ++k) m.normal[t[k]] += n;  // area-weighted
  }
  for (Vec3& n : m.normal) n = n.squaredNorm() > 0.0 ? Vec3(n.normalized()) : Vec3::UnitY();
  return m;
}

SurfaceMesh collider_mesh(const Collider& c, const Vec3& focus, double extent, int segments,
                          int rings) {
  switch (c.type) {
    case ColliderType::sphere:
      return sphere(c, segments, rings);
    case ColliderType::plane:
      return plane(c, focus, extent);
    case ColliderType::capsule:
      return capsule(c, segments, rings);
    case ColliderType::box:
      return box(c);
    case ColliderType::mesh:
      return triangle_mesh(c, true);
  }
  return {};
}

}  // namespace drape::io
