// A push at one point of the cloth: how a collider holds out the cloth between its particles (a
// moving round body's triangle contacts, a box's or mesh's sharp features). The point
// Σ w[k]·x[k] of two or three particles moves out along a normal, shared between them by their
// weights and inverse masses, and each method's state carries it out with Coulomb friction on
// the point's slide over the surface (StateCloth here for the methods that keep velocities;
// xpbd's on positions).
#pragma once

#include <cstdint>

#include "drape/cloth.h"
#include "drape/collider.h"

namespace drape {

/// A push at one point of the cloth: the point Σ w[k]·x[index[k]] (count particles) moves by
/// depth along the unit n.
struct PointPush {
  int count = 0;
  int32_t index[3] = {0, 0, 0};
  double w[3] = {1.0, 0.0, 0.0};
  Vec3 n = Vec3::UnitY();
  double depth = 0.0;
};

/// The moves of a push's particles: each by w·inverse mass·depth / Σ w²·inverse mass along n
/// (the position-based rule for a constraint on Σ w[k]·x[k]); false where all are fixed.
template <class InvMass>
bool push_moves(const PointPush& push, InvMass inv_mass, Vec3 moves[3], double& sum) {
  sum = 0.0;
  for (int k = 0; k < push.count; ++k) sum += push.w[k] * push.w[k] * inv_mass(push.index[k]);
  if (!(sum > 0.0)) return false;
  for (int k = 0; k < push.count; ++k)
    moves[k] = (push.w[k] * inv_mass(push.index[k]) * push.depth / sum) * push.n;
  return true;
}

/// The change `slip` (a velocity or a move of the contact point relative to the surface) less
/// its part along n, shortened by friction·`normal` (Coulomb's bound on what a normal change of
/// that size can hold), never reversed: what friction takes off the point.
inline Vec3 friction_change(const Vec3& slip, const Vec3& n, double friction, double normal) {
  const Vec3 tangential = slip - slip.dot(n) * n;
  const double length = tangential.norm();
  const double bound = friction * normal;
  return length <= bound ? tangential : Vec3(tangential * (bound / length));
}

/// The cloth's state as a target of point pushes (FeatureContacts::apply, the triangle contacts
/// in resolve_contacts), for the methods that keep it there:
/// a push moves the particles, removes the point's velocity into the surface (relative to the
/// surface's own) and, with Coulomb friction, its sliding by up to friction × that change.
struct StateCloth {
  ClothState& state;
  Vec3 position(int32_t i) const { return state.x[i]; }
  void push(const PointPush& push, const Collider& c) {
    Vec3 moves[3];
    double sum = 0.0;
    if (!push_moves(
            push, [&](int32_t i) { return state.inv_mass[i]; }, moves, sum))
      return;
    Vec3 point = Vec3::Zero(), v = Vec3::Zero();
    for (int k = 0; k < push.count; ++k) {
      state.x[push.index[k]] += moves[k];
      point += push.w[k] * state.x[push.index[k]];
      v += push.w[k] * state.v[push.index[k]];
    }
    const Vec3 rel = v - c.surface_velocity(point);
    const double vn = rel.dot(push.n);
    if (vn >= 0.0) return;
    const Vec3 change = -vn * push.n - friction_change(rel, push.n, c.friction, -vn);
    for (int k = 0; k < push.count; ++k)
      state.v[push.index[k]] += (push.w[k] * state.inv_mass[push.index[k]] / sum) * change;
  }
};

}  // namespace drape
