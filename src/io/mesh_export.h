// Mesh export: the cloth's current surface with positions, normals, uv and triangles, as
// Wavefront OBJ or binary PLY (both open in Blender and MeshLab).
#pragma once

#include <string>

#include "drape/cloth.h"

namespace drape::io {

enum class MeshFormat { obj, ply };

/// Writes the mesh to `file` as io::OutputFile does (a reader never sees half a file). Throws
/// OutputError naming the file if it cannot be written.
void write_mesh(const std::string& file, MeshFormat format, const ClothModel& model,
                const ClothState& state);

}  // namespace drape::io
