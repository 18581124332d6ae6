#include "io/mesh_export.h"

#include <bit>
#include <cstdio>

#include "io/output_file.h"

namespace drape::io {

namespace {

void write_obj(FILE* f, const ClothModel& m, const ClothState& s) {
  std::fprintf(f, "# drape cloth: %d particles, %zu triangles\n", m.size(), m.triangles.size());
  for (const Vec3& x : s.x) std::fprintf(f, "v %.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  for (const Vec3& n : s.normal) std::fprintf(f, "vn %.6f %.6f %.6f\n", n.x(), n.y(), n.z());
  // Texture coordinates as the cloth had them: per corner where a mesh has seams, per vertex
  // otherwise; none for a mesh that came without.
  const bool corners = !m.triangle_texcoords.empty();
  if (corners)
    for (const Vec2& t : m.texcoords) std::fprintf(f, "vt %.6f %.6f\n", t.x(), 1.0 - t.y());
  else if (m.has_texcoords)
    for (const Vec2& t : m.uv) std::fprintf(f, "vt %.6f %.6f\n", t.x(), 1.0 - t.y());
  for (size_t k = 0; k < m.triangles.size(); ++k) {
    const Triangle& t = m.triangles[k];
    std::fprintf(f, "f");
    for (int c = 0; c < 3; ++c) {
      const int v = t[c] + 1;  // OBJ counts from 1
      if (corners)
        std::fprintf(f, " %d/%d/%d", v, m.triangle_texcoords[k][c] + 1, v);
      else if (m.has_texcoords)
        std::fprintf(f, " %d/%d/%d", v, v, v);
      else
        std::fprintf(f, " %d//%d", v, v);
    }
    std::fprintf(f, "\n");
  }
}

void write_ply(FILE* f, const ClothModel& m, const ClothState& s) {
  // Texture coordinates per vertex (PLY has no per-corner ones: a seam's vertex keeps its first
  // corner's), and only for a cloth that had them.
  const bool uv = m.has_texcoords;
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\ncomment drape cloth\n"
               "element vertex %d\n"
               "property float x\nproperty float y\nproperty float z\n"
               "property float nx\nproperty float ny\nproperty float nz\n%s"
               "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
               m.size(), uv ? "property float s\nproperty float t\n" : "", m.triangles.size());
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes little endian");
  for (int32_t i = 0; i < m.size(); ++i) {
    const float v[8] = {float(s.x[i].x()),      float(s.x[i].y()),       float(s.x[i].z()),
                        float(s.normal[i].x()), float(s.normal[i].y()),  float(s.normal[i].z()),
                        float(m.uv[i].x()),     float(1.0 - m.uv[i].y())};
    std::fwrite(v, sizeof(float), uv ? 8 : 6, f);
  }
  for (const Triangle& t : m.triangles) {
    const unsigned char three = 3;
    std::fwrite(&three, 1, 1, f);
    std::fwrite(t.data(), sizeof(int32_t), 3, f);
  }
}

}  // namespace

void write_mesh(const std::string& file, MeshFormat format, const ClothModel& model,
                const ClothState& state) {
  OutputFile out(file);
  if (format == MeshFormat::obj)
    write_obj(out.get(), model, state);
  else
    write_ply(out.get(), model, state);
  out.commit();
}

void write_obj(const std::string& file, const ClothMesh& mesh, const std::string& comment) {
  OutputFile out(file);
  FILE* f = out.get();
  std::fprintf(f, "# %s\n# %zu vertices, %zu triangles\n", comment.c_str(), mesh.positions.size(),
               mesh.triangles.size());
  for (const Vec3& x : mesh.positions) std::fprintf(f, "v %.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  for (const Vec2& t : mesh.texcoords) std::fprintf(f, "vt %.6f %.6f\n", t.x(), t.y());
  const bool textured = !mesh.triangle_texcoords.empty();
  for (size_t k = 0; k < mesh.triangles.size(); ++k) {
    std::fprintf(f, "f");
    for (int c = 0; c < 3; ++c) {
      if (textured)
        std::fprintf(f, " %d/%d", mesh.triangles[k][c] + 1, mesh.triangle_texcoords[k][c] + 1);
      else
        std::fprintf(f, " %d", mesh.triangles[k][c] + 1);
    }
    std::fprintf(f, "\n");
  }
  out.commit();
}

}  // namespace drape::io
