// Mesh export: the cloth's current surface with positions, normals, uv and triangles, as
// Wavefront OBJ or binary PLY (both open in Blender and MeshLab).
#pragma once

#include <string>

#include "drape/cloth.h"
#include "drape/mesh.h"

namespace drape::io {

enum class MeshFormat { obj, ply };

/// Writes the mesh to `file` as io::OutputFile does (a reader never sees half a file). Throws
/// OutputError naming the file if it cannot be written.
void write_mesh(const std::string& file, MeshFormat format, const ClothModel& model,
                const ClothState& state);

/// Writes a mesh at rest (vertices, texture coordinates, triangles) as OBJ, as io::OutputFile
/// writes, with `comment` on its first line.
void write_obj(const std::string& file, const ClothMesh& mesh, const std::string& comment);

}  // namespace drape::io
