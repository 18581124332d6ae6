// A collider's sharp features: the convex edges and corners of a box or a closed mesh. Particle
// contacts keep the cloth's particles out of a body, but where the body turns sharply a cloth
// triangle lying across it meets the surface between its particles: a table's edge or a box's
// corner pokes through a coarse cloth that rests on it. The contacts with these features
// (feature_contacts.h) keep the cloth's edges and faces out too.
#pragma once

#include <cstdint>
#include <vector>

#include "collision/triangle_shape.h"
#include "drape/math.h"

namespace drape {

/// Edges and corners in the collider's definition frame (what its pose moves).
struct SharpFeatures {
  /// A convex edge a–b between faces with outward normals n1 and n2 (unit).
  struct Edge {
    Vec3 a, b, n1, n2;
  };
  /// A convex corner p, pointing out along n (unit, the angle-weighted normal); its faces'
  /// normals are face_normals[first .. first + count).
  struct Corner {
    Vec3 p, n;
    int32_t first = 0, count = 0;
  };
  std::vector<Edge> edges;
  std::vector<Corner> corners;
  std::vector<Vec3> face_normals;
  bool empty() const { return edges.empty() && corners.empty(); }
};

/// The features of a closed mesh (its triangles facing out): edges whose faces turn by more
/// than `angle` (radians) and outward, and vertices around which all neighbours lie below the
/// vertex's normal plane and some face turns from it by more than angle/2 (a box's corners, a
/// cone's tip). A smooth mesh (a finely tessellated sphere) has none.
SharpFeatures sharp_features(const TriangleShape& shape, double angle);

/// The twelve edges and eight corners of a box (centre, half extents, axes as columns).
SharpFeatures box_features(const Vec3& center, const Vec3& half_extents, const Mat3& axes);

/// The turn between faces above which an edge or a corner is sharp: a cloth cell lying across
/// a gentler one dips into the body by less than an eighth of its width.
inline constexpr double kSharpAngle = 0.35;  // radians, 20°

}  // namespace drape
