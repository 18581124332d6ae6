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
  for (const Vec2& t : m.uv) std::fprintf(f, "vt %.6f %.6f\n", t.x(), 1.0 - t.y());
  for (const Triangle& t : m.triangles) {
    const int a = t[0] + 1, b = t[1] + 1, c = t[2] + 1;  // OBJ counts from 1
    std::fprintf(f, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, b, b, b, c, c, c);
  }
}

void write_ply(FILE* f, const ClothModel& m, const ClothState& s) {
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\ncomment drape cloth\n"
               "element vertex %d\n"
               "property float x\nproperty float y\nproperty float z\n"
               "property float nx\nproperty float ny\nproperty float nz\n"
               "property float s\nproperty float t\n"
               "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
               m.size(), m.triangles.size());
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes little endian");
  for (int32_t i = 0; i < m.size(); ++i) {
    const float v[8] = {float(s.x[i].x()),      float(s.x[i].y()),      float(s.x[i].z()),
                        float(s.normal[i].x()), float(s.normal[i].y()), float(s.normal[i].z()),
                        float(m.uv[i].x()),     float(1.0 - m.uv[i].y())};
    std::fwrite(v, sizeof v, 1, f);
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
  if (format == MeshFormat::obj) write_obj(out.get(), model, state);
  else write_ply(out.get(), model, state);
  out.commit();
}

}  // namespace drape::io
