// Wavefront OBJ in: a cloth's shape from a file, read with tinyobjloader after a check of every
// line, so that a problem is reported with its line.
#pragma once

#include <string>

#include "drape/mesh.h"

namespace drape::io {

/// The largest OBJ file read (bytes): far past any cloth the memory budget lets run.
inline constexpr int64_t kMaxObjBytes = int64_t{512} << 20;

/// Reads `file` as a cloth mesh: vertices, faces (polygons split into fans of triangles, each
/// remembering its face's line), texture coordinates when every face has them. Normals,
/// materials, lines and points are ignored; no other file is opened (a `mtllib` names one).
/// Throws InputError with an empty path and a problem naming the line: a missing or unreadable
/// file, a statement that does not parse, a non-finite coordinate, an index out of range.
/// Whether the mesh can be a cloth (triangles, areas, manifold edges) is check()'s business.
ClothMesh read_obj(const std::string& file);

}  // namespace drape::io
