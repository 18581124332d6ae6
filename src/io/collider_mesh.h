// Colliders as triangle meshes, for exports and the viewer: a sphere as a UV sphere, a plane as
// a large square around the cloth, a capsule as a sphere's halves joined by a cylinder, a box as
// its six faces, a mesh as its triangles; each where its pose puts it now.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "drape/collider.h"

namespace drape::io {

struct SurfaceMesh {
  std::vector<Vec3> position;                     ///< m
  std::vector<Vec3> normal;                       ///< unit, outward
  std::vector<std::array<int32_t, 3>> triangles;  ///< counter-clockwise seen from outside
};

/// A sphere of `segments` around its axis (y) and `rings` from pole to pole, each pole a fan
/// (no degenerate triangles); a plane as a square of side `extent` centred where `focus` (the
/// cloth's centre) projects onto it. The surface drawn is the collider's, without thickness.
SurfaceMesh collider_mesh(const Collider& c, const Vec3& focus, double extent, int segments = 32,
                          int rings = 16);

/// A mesh collider's triangles (empty for other types), posed (where it is now) or in the frame
/// of its definition (`posed` false: for a renderer that places it with c.pose).
SurfaceMesh triangle_mesh(const Collider& c, bool posed);

}  // namespace drape::io
