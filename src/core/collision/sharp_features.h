// A collider's sharp features: the convex edges and corners of a box or a mesh, and an open
// mesh's rim. Particle contacts keep the cloth's particles out of a body, but where the body
// turns sharply a cloth triangle lying across it meets the surface between its particles: a
// table's edge or a box's corner pokes through a coarse cloth that rests on it, and the rim of
// an open sheet (a blade: its surface turns by 180° there) cuts through a cloth draped over it.
// The contacts with these features (feature_contacts.h) keep the cloth's edges and faces out
// too.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/triangle_shape.h"
#include "drape/math.h"

namespace drape {

/// Edges and corners in the collider's definition frame (what its pose moves).
struct SharpFeatures {
  /// A convex edge a–b between faces with outward normals n1 and n2 (unit), and `out`, the
  /// unit direction a cloth edge passing inside it is pushed along: between n1 and n2, or for
  /// an open mesh's rim (a blade: n2 = −n1) along its face away from it. A blade also has the
  /// `out` of the rim's next edges at a and at b (zero where the rim does not go on through
  /// one other edge there): past its ends, the sheet lies behind both.
  struct Edge {
    Vec3 a, b, n1, n2, out;
    bool blade = false;
    Vec3 next_out[2] = {Vec3::Zero(), Vec3::Zero()};
  };
  /// A convex corner p, pointing out along n (unit, the angle-weighted normal); its faces'
  /// normals are face_normals[first .. first + count).
  /// On an open mesh's rim (rim = true), n lies along the sheet, away from it, `along` are
  /// the unit directions of the rim's two edges from p, and there are no face normals
  /// (count = 0).
  struct Corner {
    Vec3 p, n;
    int32_t first = 0, count = 0;
    bool rim = false;
    Vec3 along[2] = {Vec3::Zero(), Vec3::Zero()};
  };
  std::vector<Edge> edges;
  std::vector<Corner> corners;
  std::vector<Vec3> face_normals;
  bool empty() const { return edges.empty() && corners.empty(); }
};

/// The features of a mesh: edges whose faces turn by more than `angle` (radians) and outward,
/// and vertices around which all neighbours lie below the vertex's normal plane and some face
/// turns from it by more than angle/2 (a box's corners, a cone's tip). A closed mesh's
/// triangles face out; an open mesh is two-sided, so its edges and vertices count on whichever
/// side they point out to, and its rim adds blades (every edge of one triangle) and the rim's
/// corners (where the faces round a rim vertex span less than 180° − angle: a sheet's
/// corners). A smooth closed mesh (a finely tessellated sphere) has none.
SharpFeatures sharp_features(const TriangleShape& shape, double angle);

/// The twelve edges and eight corners of a box (centre, half extents, axes as columns).
SharpFeatures box_features(const Vec3& center, const Vec3& half_extents, const Mat3& axes);

/// The turn between faces above which an edge or a corner is sharp: a cloth cell lying across
/// a gentler one dips into the body by less than an eighth of its width.
inline constexpr double kSharpAngle = 0.35;  // radians, 20°

}  // namespace drape
