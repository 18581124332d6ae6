#include "drape/collider.h"

#include <algorithm>
#include <limits>

#include "collision/motion.h"
#include "collision/sharp_features.h"
#include "collision/triangle_contact.h"
#include "collision/triangle_shape.h"
#include "parallel.h"

namespace drape {

Collider make_collider(const ColliderDef& def) {
  Collider c;
  c.type = def.type;
  c.friction = def.friction;
  c.thickness = def.thickness;
  switch (def.type) {
    case ColliderType::sphere:
      c.center = def.center;
      c.radius = def.radius;
      c.bound_center = c.center;
      c.bound_radius = c.radius;
      break;
    case ColliderType::plane:
      c.center = def.center;
      c.normal = def.normal.normalized();
      c.bound_center = c.center;
      c.bound_radius = std::numeric_limits<double>::infinity();
      break;
    case ColliderType::capsule:
      c.a = def.a;
      c.b = def.b;
      c.radius = def.radius;
      c.center = 0.5 * (def.a + def.b);
      c.bound_center = c.center;
      c.bound_radius = 0.5 * (def.b - def.a).norm() + c.radius;
      break;
    case ColliderType::box:
      c.center = def.center;
      c.half_extents = def.half_extents;
      c.rotation = rotation_xyz(def.rotate);
      c.bound_center = c.center;
      c.bound_radius = def.half_extents.norm();
      c.features =
          std::make_shared<const SharpFeatures>(box_features(c.center, c.half_extents, c.rotation));
      break;
    case ColliderType::mesh: {
      std::vector<Vec3> vertices;
      if (def.mesh) {
        vertices.reserve(def.mesh->positions.size());
        for (const Vec3& p : def.mesh->positions) vertices.push_back(def.transform.apply(p));
      }
      auto shape = std::make_shared<const TriangleShape>(
          std::move(vertices), def.mesh ? def.mesh->triangles : std::vector<Triangle>{});
      c.center = def.transform.translate;
      // The sphere about the box's centre through the farthest vertex: tighter than the box's
      // half-diagonal (a sphere mesh's own radius rather than √3 times it).
      c.bound_center = 0.5 * (shape->lo() + shape->hi());
      for (const Vec3& v : shape->vertices())
        c.bound_radius = std::max(c.bound_radius, (v - c.bound_center).norm());
      auto features = std::make_shared<SharpFeatures>(sharp_features(*shape, kSharpAngle));
      if (!features->empty()) c.features = std::move(features);
      c.mesh = std::move(shape);
      break;
    }
  }
  return c;
}

namespace {

// entered_elsewhere for a mesh, from `start` (the particle's start carried by the body's
// motion) to x: the triangle its path crosses first, where x is not on the side it came from
// by the nearest surface's reckoning. On a closed mesh only a path from outside counts.
bool mesh_entered_elsewhere(const Collider& c, const Vec3& start, const Vec3& x, Vec3& normal,
                            double& gap) {
  if (!c.mesh) return false;
  // A move within the contact's thickness ends where the nearest surface tells its side.
  if ((x - start).lpNorm<1>() < c.thickness) return false;
  const Mat3& R = c.pose.rotation;
  const Vec3 a = R.transpose() * (start - c.pose.translation);
  const Vec3 b = R.transpose() * (x - c.pose.translation);
  const int32_t tri = c.mesh->first_crossing(a, b);
  if (tri < 0) return false;
  const Vec3& on = c.mesh->vertices()[c.mesh->triangles()[tri][0]];
  Vec3 n = c.mesh->face_normals()[tri];
  const bool outside = n.dot(a - on) > 0.0;
  if (c.mesh->closed() && !outside) return false;  // it started inside: the nearest surface
  if (!outside) n = -n;                            // an open mesh's side it came from
  Vec3 nearest;
  c.mesh->signed_distance(b, nearest);
  if (nearest.dot(n) > 0.0) return false;  // the nearest surface sends it back that side too
  normal = R * n;
  gap = n.dot(b - on) - c.thickness;
  return true;
}

// entered_elsewhere for a box, from `start` to x.
bool box_entered_elsewhere(const Collider& c, const Vec3& start, const Vec3& x, Vec3& normal,
                           double& gap) {
  // A move shorter than the box's least half extent (|x| + |y| + |z| bounds its length) ends
  // nearer the face it came in by than the one opposite: the nearest face is that one, or one
  // beside it round an edge, never the far side. Most moves are that short.
  if ((x - start).lpNorm<1>() < c.half_extents.minCoeff()) return false;
  const Vec3 p = c.rotation.transpose() * (start - c.center);
  const Vec3 q = c.rotation.transpose() * (x - c.center);
  const Vec3& half = c.half_extents;
  // The segment p–q clipped against the solid box's three slabs: it meets the box over
  // [enter, leave], entering through the face of the slab it reaches last. (The solid, not the
  // box widened by the thickness: a path that only grazes the thickness round an edge keeps
  // the nearest surface's rounded way out.)
  double enter = 0.0, leave = 1.0;
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    const double d = q[k] - p[k];
    if (d == 0.0) {
      if (std::abs(p[k]) > half[k]) return false;  // beside the slab all the way
      continue;
    }
    double t0 = (-half[k] - p[k]) / d, t1 = (half[k] - p[k]) / d;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > enter) enter = t0, axis = k;
    leave = std::min(leave, t1);
  }
  // axis < 0: it started inside (or on) the box, whose nearest face is the way out.
  if (axis < 0 || !(enter <= leave)) return false;
  const double side = p[axis] > 0.0 ? 1.0 : -1.0;
  // Inside and nearest the face it came in by (shape_distance's face): the same way out.
  const Vec3 depth = q.cwiseAbs() - half;
  int nearest = 0;
  if (depth.maxCoeff(&nearest) <= 0.0 && nearest == axis && (q[axis] > 0.0) == (side > 0.0))
    return false;
  normal = side * c.rotation.col(axis);
  gap = side * q[axis] - half[axis] - c.thickness;
  return true;
}

}  // namespace

bool entered_elsewhere(const Collider& c, const Vec3& from, const Vec3& x, Vec3& normal,
                       double& gap) {
  if (c.type != ColliderType::box && c.type != ColliderType::mesh) return false;
  // The particle's start where the body's motion since the substep began has carried it (the
  // inverse of the map surface_move undoes): its path relative to the body.
  const Vec3 start =
      c.moving ? Vec3(c.back_rotation.transpose() * (from - c.back_to) + c.back_from) : from;
  return c.type == ColliderType::box ? box_entered_elsewhere(c, start, x, normal, gap)
                                     : mesh_entered_elsewhere(c, start, x, normal, gap);
}

std::vector<Collider> make_colliders(const std::vector<ColliderDef>& defs) {
  std::vector<Collider> out;
  out.reserve(defs.size());
  for (const ColliderDef& d : defs) out.push_back(make_collider(d));
  return out;
}

double shape_distance(const Collider& c, const Vec3& x, Vec3& normal) {
  switch (c.type) {
    case ColliderType::capsule: {
      // The closest point of the axis a–b (a = b: a sphere).
      const Vec3 ab = c.b - c.a;
      const double len2 = ab.squaredNorm();
      const double s = len2 > 0.0 ? std::clamp((x - c.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const Vec3 d = x - (c.a + s * ab);
      const double len = d.norm();
      if (len > 0.0) {
        normal = d / len;
      } else {  // on the axis: any direction across it
        normal = len2 > 0.0 ? Vec3(ab.unitOrthogonal()) : Vec3::UnitY();
      }
      return len - c.radius;
    }
    case ColliderType::box: {
      // In the box's frame: outside, the distance to the nearest point of the box; inside, to
      // the nearest face (Quílez's box distance, with its gradient as the normal).
      const Vec3 p = c.rotation.transpose() * (x - c.center);
      const Vec3 q = p.cwiseAbs() - c.half_extents;
      const Vec3 sign = p.unaryExpr([](double v) { return v < 0.0 ? -1.0 : 1.0; });
      if ((q.array() > 0.0).any()) {
        const Vec3 out = q.cwiseMax(Vec3::Zero());
        const double dist = out.norm();
        normal = c.rotation * out.cwiseProduct(sign) / dist;
        return dist;
      }
      int axis = 0;
      const double dist = q.maxCoeff(&axis);
      normal = sign[axis] * c.rotation.col(axis);
      return dist;
    }
    case ColliderType::mesh: {
      if (!c.mesh) {
        normal = Vec3::UnitY();
        return std::numeric_limits<double>::infinity();
      }
      const Mat3& R = c.pose.rotation;
      Vec3 n;
      const double dist = c.mesh->signed_distance(R.transpose() * (x - c.pose.translation), n);
      normal = R * n;
      return dist;
    }
    case ColliderType::sphere:
    case ColliderType::plane:
      break;
  }
  return signed_distance(c, x, normal);
}

void resolve_contacts(const std::vector<Collider>& colliders, ClothState& state) {
  if (colliders.empty()) return;
  const int32_t n = static_cast<int32_t>(state.x.size());
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t i = 0; i < n; ++i) {
    if (state.inv_mass[i] == 0.0) continue;
    for (const Collider& c : colliders) resolve_contact(c, state.x[i], state.v[i]);
  }
}

void resolve_contacts(const std::vector<Collider>& colliders, const ClothModel& model,
                      ClothState& state) {
  if (!any_holds_triangles_out(colliders)) return resolve_contacts(colliders, state);
  const int32_t n = static_cast<int32_t>(state.x.size());
  for (const Collider& c : colliders) {
#pragma omp parallel for schedule(static) if (worth_threads(n))
    for (int32_t i = 0; i < n; ++i)
      if (state.inv_mass[i] != 0.0) resolve_contact(c, state.x[i], state.v[i]);
    if (!holds_triangles_out(c)) continue;
    StateCloth cloth{state};
    for (const Triangle& t : model.triangles) {
      PointPush push;
      if (!triangle_push(c, state.x[t[0]], state.x[t[1]], state.x[t[2]], push)) continue;
      for (int k = 0; k < 3; ++k) push.index[k] = t[k];
      cloth.push(push, c);
    }
  }
}

double max_penetration(const std::vector<Collider>& colliders, const std::vector<Vec3>& x) {
  double deepest = 0.0;
  Vec3 n;
  for (const Vec3& p : x)
    for (const Collider& c : colliders) deepest = std::max(deepest, -signed_distance(c, p, n));
  return deepest;
}

}  // namespace drape
