#include "drape/collider.h"

#include <algorithm>
#include "parallel.h"

namespace drape {

Collider make_collider(const ColliderDef& def) {
  Collider c;
  c.type = def.type;
  c.center = def.center;
  c.radius = def.radius;
  c.normal = def.normal.normalized();
  c.friction = def.friction;
  c.thickness = def.thickness;
  return c;
}

std::vector<Collider> make_colliders(const std::vector<ColliderDef>& defs) {
  std::vector<Collider> out;
  out.reserve(defs.size());
  for (const ColliderDef& d : defs) out.push_back(make_collider(d));
  return out;
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

double max_penetration(const std::vector<Collider>& colliders, const std::vector<Vec3>& x) {
  double deepest = 0.0;
  Vec3 n;
  for (const Vec3& p : x)
    for (const Collider& c : colliders) deepest = std::max(deepest, -signed_distance(c, p, n));
  return deepest;
}

}  // namespace drape
