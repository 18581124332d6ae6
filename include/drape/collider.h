// Colliders: signed distances and the contact response shared by every solver.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "drape/cloth.h"
#include "drape/scene.h"

namespace drape {

class TriangleShape;
struct SharpFeatures;

/// A rigid pose: a point p of the collider's definition is at rotation·p + translation.
struct Pose {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();  ///< m
  Vec3 apply(const Vec3& p) const { return rotation * p + translation; }
};

/// A collider ready for queries, made from a ColliderDef and posed at a time (its motion):
/// the fields below are where the surface is now, in world coordinates.
struct Collider {
  ColliderType type = ColliderType::sphere;
  Vec3 center = Vec3::Zero();                 ///< m, sphere or box centre, a point on the plane
  double radius = 0.0;                        ///< m, sphere and capsule
  Vec3 normal = Vec3::UnitY();                ///< unit, plane only: the side the cloth stays on
  Vec3 a = Vec3::Zero();                      ///< m, capsule: one end of its axis
  Vec3 b = Vec3::Zero();                      ///< m, capsule: the other end
  Vec3 half_extents = Vec3::Zero();           ///< m, box
  Mat3 rotation = Mat3::Identity();           ///< box: its axes (columns) in world coordinates
  std::shared_ptr<const TriangleShape> mesh;  ///< mesh: triangles and BVH, definition frame
  /// box and closed mesh: convex edges and corners, definition frame (null: none)
  std::shared_ptr<const SharpFeatures> features;
  double friction = 0.0;                      ///< Coulomb coefficient (dimensionless)
  double thickness = 0.0;                     ///< m, gap kept between the cloth and the surface
  Pose pose;  ///< where the definition's frame is now (identity: unmoved)
  /// A sphere around the whole surface (centre, radius in m), infinite for a plane: a point
  /// farther than bound_radius + thickness from bound_center touches nothing.
  Vec3 bound_center = Vec3::Zero();
  double bound_radius = 0.0;
  // The motion over the substep that ends at this pose (see surface_move).
  bool moving = false;                                    ///< false: the surface stands still
  Mat3 back_rotation = Mat3::Identity();                  ///< start rotation · this rotationᵀ
  Vec3 back_from = Vec3::Zero(), back_to = Vec3::Zero();  ///< translations now, at the start
  double move_time = 0.0;  ///< s, since the substep's start (what surface_move spans)
  /// The displacement (m) over the substep of the surface's point now at x (0 if still).
  Vec3 surface_move(const Vec3& x) const {
    return moving ? Vec3(x - (back_rotation * (x - back_from) + back_to)) : Vec3::Zero();
  }
  /// The surface's mean velocity (m/s) over that time at the point now at x (0 if still).
  Vec3 surface_velocity(const Vec3& x) const {
    return moving && move_time > 0.0 ? Vec3(surface_move(x) / move_time) : Vec3::Zero();
  }
  /// Sphere and plane standing still: the vectorised PositionContact applies.
  bool simple() const {
    return !moving && (type == ColliderType::sphere || type == ColliderType::plane);
  }
};

/// The collider a definition describes, as defined (unmoved); make_colliders converts a
/// scene's list. A mesh collider builds its BVH here (once).
Collider make_collider(const ColliderDef& def);
std::vector<Collider> make_colliders(const std::vector<ColliderDef>& defs);

/// Signed distance from x to a capsule's, box's or mesh's surface (see signed_distance).
double shape_distance(const Collider& c, const Vec3& x, Vec3& normal);

/// Signed distance from x to the surface (negative inside; an open mesh has no inside: its
/// distance is unsigned) and the outward normal there (the direction from the surface's
/// closest point to x).
inline double signed_distance(const Collider& c, const Vec3& x, Vec3& normal) {
  if (c.type == ColliderType::plane) {
    normal = c.normal;
    return c.normal.dot(x - c.center);
  }
  if (c.type != ColliderType::sphere) return shape_distance(c, x, normal);
  const Vec3 d = x - c.center;
  const double len = d.norm();
  normal = len > 0.0 ? Vec3(d / len) : Vec3::UnitY();
  return len - c.radius;
}

/// Whether x is surely farther from the surface than the thickness plus `margin` (m), by the
/// bounding sphere alone: queries of a mesh or box far from the cloth are skipped this way.
inline bool clear_of(const Collider& c, const Vec3& x, double margin = 0.0) {
  const double reach = c.bound_radius + c.thickness + margin;
  return (x - c.bound_center).squaredNorm() > reach * reach;
}

/// If x lies closer to the surface than the thickness, moves it out along the normal to the
/// thickness, removes the normal velocity into the surface, and applies Coulomb friction to the
/// tangential velocity: its change is at most friction × the normal velocity change. Velocities
/// are taken relative to the surface's (a moving collider carries the cloth it touches).
/// Returns true on contact.
inline bool resolve_contact(const Collider& c, Vec3& x, Vec3& v) {
  if (clear_of(c, x)) return false;
  Vec3 n;
  const double gap = signed_distance(c, x, n) - c.thickness;
  if (gap >= 0.0) return false;
  x -= gap * n;
  const Vec3 surface = c.surface_velocity(x);
  const Vec3 rel = v - surface;
  const double vn = rel.dot(n);
  if (vn < 0.0) {
    const Vec3 vt = rel - vn * n;
    const double vt_len = vt.norm();
    const double keep = vt_len > 0.0 ? std::max(0.0, 1.0 - c.friction * (-vn) / vt_len) : 0.0;
    v = surface + keep * vt;
  }
  return true;
}

/// Coulomb friction for a contact whose normal velocity changed by dvn ≥ 0 (m/s): the
/// tangential velocity shrinks by at most friction·dvn, never reversing. The same rule as
/// resolve_contact, for solvers that handle the normal part inside their solve.
inline void apply_friction(const Vec3& n, double dvn, double friction, Vec3& v) {
  const double vn = v.dot(n);
  const Vec3 vt = v - vn * n;
  const double vt_len = vt.norm();
  const double keep = vt_len > 0.0 ? std::max(0.0, 1.0 - friction * dvn / vt_len) : 0.0;
  v = vn * n + keep * vt;
}

/// The position-level contact of the position-based methods (Macklin et al. 2014, "Unified
/// particle physics", sec. 6.1), on scalars so that solver loops vectorise: if the particle lies
/// closer to the surface than the thickness, it moves out along the normal by the depth d, then
/// its tangential move since x_prev is cancelled when within friction·d (static friction) or
/// shortened by friction·d (kinetic). Acting on positions, it holds cloth on a slope that
/// velocity-level friction would let creep a little every substep. Real is the solver's storage
/// type.
template <typename Real>
struct PositionContact {
  explicit PositionContact(const Collider& c)
      : sphere(c.type == ColliderType::sphere),
        nx(static_cast<Real>(c.normal.x())),
        ny(static_cast<Real>(c.normal.y())),
        nz(static_cast<Real>(c.normal.z())),
        radius(static_cast<Real>(c.radius)),
        thickness(static_cast<Real>(c.thickness)),
        friction(static_cast<Real>(c.friction)),
        reach_squared(
            static_cast<Real>(1.001 * (c.radius + c.thickness) * (c.radius + c.thickness))) {}

  /// How surely apply() leaves a particle at (px, py, pz) (x minus the collider's centre) as it
  /// is: positive only where it does, with a margin far above the round-off of apply's own test,
  /// so a solver may skip a run of particles whose least clearance is positive. No square root;
  /// branch-free, so a min-reduction over a run vectorises.
  Real clearance(Real px, Real py, Real pz) const {
    const Real to_sphere = px * px + py * py + pz * pz - reach_squared;
    const Real scale = std::abs(px) + std::abs(py) + std::abs(pz) + thickness;
    const Real to_plane = nx * px + ny * py + nz * pz - thickness - Real(1e-3) * scale;
    return sphere ? to_sphere : to_plane;
  }

  /// (px, py, pz) is x minus the collider's centre, (mx, my, mz) the move x − x_prev, updated
  /// in place; `movable` false (a pinned particle) leaves it as it is. Branch-free.
  void apply(bool movable, Real px, Real py, Real pz, Real& mx, Real& my, Real& mz) const {
    // The outward normal and the signed gap to the surface's thickness.
    const Real len = std::sqrt(px * px + py * py + pz * pz);
    const Real inv = len > Real(0) ? Real(1) / len : Real(0);
    const Real ux = sphere ? px * inv : nx, uz = sphere ? pz * inv : nz;
    const Real uy = !sphere ? ny : len > Real(0) ? py * inv : Real(1);  // the centre: push up
    const Real gap = (sphere ? len - radius : ux * px + uy * py + uz * pz) - thickness;
    const bool hit = movable && gap < Real(0);
    const Real out = hit ? -gap : Real(0);
    mx += out * ux;
    my += out * uy;
    mz += out * uz;
    const Real normal_move = mx * ux + my * uy + mz * uz;
    const Real tx = mx - normal_move * ux, ty = my - normal_move * uy, tz = mz - normal_move * uz;
    const Real slide = std::sqrt(tx * tx + ty * ty + tz * tz), grip = friction * out;
    const Real cancel = !hit ? Real(0) : slide <= grip ? Real(1) : grip / slide;
    mx -= cancel * tx;
    my -= cancel * ty;
    mz -= cancel * tz;
  }

  bool sphere;
  Real nx, ny, nz;  ///< a plane's normal
  Real radius, thickness, friction;
  Real reach_squared;  ///< a sphere's (radius + thickness)², widened by 0.1% (see clearance)
};

/// For a box or a mesh: whether a particle that moved from `from` (where it stood as the
/// substep began) to x crossed the surface into the body, or through it, so that the nearest
/// surface would push it out of the wrong side: a plate thinner than a step's move is crossed
/// (cloth falling at 10 m/s onto a 1 cm plate in steps of 4 cm went through it). A box: where
/// its path entered the solid box through a face other than the one nearest x, or passed
/// through it. A mesh: where its path crosses a triangle (the one nearest `from`; on a closed
/// mesh, from outside) and x's nearest surface faces the other way. Sets `normal` to the side it
/// came in by (outward) and `gap` to x's signed distance from that face's plane moved out by the
/// thickness (negative behind it). The path is taken relative to the body: for a moving body
/// `from` is carried by the body's motion since the substep's start. A move shorter than a box's
/// least half extent or a mesh's thickness is not followed (false): it ends where the nearest
/// surface is the way out. False for spheres, capsules and planes, whose nearest side is the
/// entry side (ColliderSet::substeps_for keeps steps short of a ball's middle).
bool entered_elsewhere(const Collider& c, const Vec3& from, const Vec3& x, Vec3& normal,
                       double& gap);

/// The way out for a particle at x that moved there from `from`: the side it came in by where it
/// entered a box or a mesh elsewhere (entered_elsewhere), else the nearest surface. Sets the
/// outward `normal` and the signed `gap` to the thickness (negative: that deep); false where x
/// is surely clear of the collider (its bounding sphere).
inline bool way_out(const Collider& c, const Vec3& from, const Vec3& x, Vec3& normal, double& gap) {
  if (entered_elsewhere(c, from, x, normal, gap)) return true;
  if (clear_of(c, x)) return false;
  gap = signed_distance(c, x, normal) - c.thickness;
  return true;
}

/// Moves x out to the thickness of the collider if it is closer (positions only), by way_out
/// from `from`. Returns the distance moved (0 if none) and sets `normal` to the outward normal
/// when it moved.
inline double project_out(const Collider& c, const Vec3& from, Vec3& x, Vec3& normal) {
  Vec3 n;
  double gap = 0.0;
  if (!way_out(c, from, x, n, gap) || gap >= 0.0) return 0.0;
  x -= gap * n;
  normal = n;
  return -gap;
}

/// Moves x out to the thickness of the collider if it is closer (positions only), by the
/// nearest surface. Returns the distance moved (0 if none) and sets `normal` to the outward
/// normal when it moved.
inline double project_out(const Collider& c, Vec3& x, Vec3& normal) {
  const Vec3 from = x;  // no path: entered_elsewhere finds none
  return project_out(c, from, x, normal);
}

/// PositionContact's rule for any collider, moving or not (the path of the shapes it does not
/// vectorise): x is the particle's position, `move` its move since the substep's start, both
/// changed in place; it leaves by way_out from where it began the substep. Static friction holds
/// the particle to the surface's own move over the substep, so a moving body carries what it
/// touches. Returns true on contact.
inline bool position_contact(const Collider& c, Vec3& x, Vec3& move) {
  Vec3 n;
  double gap = 0.0;
  if (!way_out(c, x - move, x, n, gap) || gap >= 0.0) return false;
  const double out = -gap;
  x += out * n;
  move += out * n;
  const Vec3 rel = move - c.surface_move(x);
  const Vec3 t = rel - rel.dot(n) * n;
  const double slide = t.norm(), grip = c.friction * out;
  const double cancel = slide <= grip ? 1.0 : grip / slide;
  x -= cancel * t;
  move -= cancel * t;
  return true;
}

/// Resolves contacts for every free particle (1/m > 0), each collider in turn.
void resolve_contacts(const std::vector<Collider>& colliders, ClothState& state);

/// resolve_contacts, keeping the cloth's triangles out of moving spheres and capsules as well
/// (src/core/collision/triangle_contact.h says why): collider after collider (a sweep's poses
/// in order), the particles and then each triangle whose point nearest the body comes closer
/// than the thickness are moved out, and the inward velocity of that point relative to the
/// surface removed.
void resolve_contacts(const std::vector<Collider>& colliders, const ClothModel& model,
                      ClothState& state);

/// Deepest distance of a particle inside any collider's surface (thickness not counted), m.
double max_penetration(const std::vector<Collider>& colliders, const std::vector<Vec3>& x);

}  // namespace drape
