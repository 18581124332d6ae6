// A cloth's shape as a triangle mesh: what a generator (the grid, an OBJ file, a shape made in
// code) produces before the cloth is built from it. The rest shape is the mesh as given: its
// edge lengths and angles are what the cloth returns to.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "drape/math.h"

namespace drape {

/// Three vertex indices, counter-clockwise seen from the cloth's front.
using Triangle = std::array<int32_t, 3>;

/// The edges of `triangles`, each once as (lower index, higher index), sorted.
std::vector<std::array<int32_t, 2>> triangle_edges(const std::vector<Triangle>& triangles);

/// A triangle mesh. Every index is checked when a cloth is built from it (check_mesh).
struct ClothMesh {
  std::vector<Vec3> positions;      ///< m, the rest shape
  std::vector<Triangle> triangles;  ///< indices into positions
  /// Texture coordinates, as many as the file had (empty: none), v up as in OBJ files. A vertex
  /// on a seam has one per side, so they are indexed per triangle corner through
  /// triangle_texcoords.
  std::vector<Vec2> texcoords;
  std::vector<Triangle> triangle_texcoords;  ///< per triangle, indices into texcoords, or empty
  /// Per triangle, the line of the file its face was read from, for messages (empty when the
  /// mesh was not read from a file).
  std::vector<int32_t> triangle_line;
};

/// Placement of a mesh as loaded: scale, then rotation about x, then y, then z (degrees,
/// right-handed: [90, 0, 0] turns +y into +z), then translation.
struct MeshTransform {
  Vec3 translate = Vec3::Zero();  ///< m
  Vec3 rotate = Vec3::Zero();     ///< degrees about x, y, z, applied in that order
  Vec3 scale = Vec3::Ones();      ///< per axis, each non-zero
  /// The rotation part as a matrix.
  Mat3 rotation() const;
  /// Where the transform takes point p.
  Vec3 apply(const Vec3& p) const;
  bool identity() const {
    return translate.isZero(0.0) && rotate.isZero(0.0) && scale == Vec3::Ones();
  }
};

/// Shapes made in code, for the shipped meshes (`drape mesh`), the benchmark and tests. Each is
/// flat in the x–z plane at y = 0 unless said otherwise, facing +y, with uv from its plane.
namespace shapes {
/// A disc of `radius` centred on the origin, triangulated irregularly: `rings` rings of
/// vertices, ring k holding about `first_ring`·k of them at a jittered angle, each ring joined to
/// the next by a strip of triangles, and a fan of first_ring triangles around the centre.
ClothMesh disc(double radius, int rings, int first_ring = 6, uint64_t seed = 1);
/// An open tube (a skirt) of `radius` and `height` around the y axis, from y = 0 down to
/// y = −height, `around` vertices per ring and `down` rings; each quad split along one diagonal.
ClothMesh tube(double radius, double height, int around, int down);
/// A swallowtail flag hanging in the x–y plane (facing +z): `width` × `height`, its pole edge
/// along x = 0 from y = 0 down to −height, a V notch `notch` deep cut into its fly edge; a grid
/// of `cols` × `rows` vertices with the triangles that lie inside the outline.
ClothMesh flag(double width, double height, double notch, int cols, int rows);
/// A square of `size` × `size` with `n` × `n` vertices, each inner vertex moved in the plane by
/// up to `jitter` of the spacing and each quad split along a diagonal chosen at random: an
/// irregular triangulation with a grid's vertex count, for benchmarks and tests.
ClothMesh jittered_grid(double size, int n, double jitter = 0.3, uint64_t seed = 1);
}  // namespace shapes

}  // namespace drape
