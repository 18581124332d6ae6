// Colliders as triangle meshes, for exports that show them beside the cloth: a sphere as a UV
// sphere, a plane as a large square around the cloth.
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

}  // namespace drape::io
