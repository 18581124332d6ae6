// The grid generator: the seed's rectangular cloth of cols × rows particles.
#include "model/model.h"

namespace drape::model {

ClothModel grid(const ClothDef& def) {
  ClothModel m;
  m.grid = {def.cols, def.rows};
  const int32_t n = def.cols * def.rows;
  const double dx = def.width / (def.cols - 1);
  const double dy = def.height / (def.rows - 1);
  // Unit vectors along the columns and the rows.
  const Vec3 across(1.0, 0.0, 0.0);
  const Vec3 down =
      def.orientation == Orientation::vertical ? Vec3(0.0, -1.0, 0.0) : Vec3(0.0, 0.0, 1.0);

  m.rest_position.resize(n);
  m.uv.resize(n);
  m.has_texcoords = true;
  m.mass.assign(n, def.mass / n);
  for (int r = 0; r < def.rows; ++r) {
    for (int c = 0; c < def.cols; ++c) {
      const int32_t i = m.index(c, r);
      m.rest_position[i] = def.origin + (c * dx) * across + (r * dy) * down;
      m.uv[i] = Vec2(static_cast<double>(c) / (def.cols - 1),
                     static_cast<double>(r) / (def.rows - 1));
    }
  }

  auto add = [&](int c0, int r0, int c1, int r1, const SpringParams& p, SpringKind kind) {
    if (c0 >= def.cols || c1 >= def.cols || r1 >= def.rows) return;
    const int32_t i = m.index(c0, r0), j = m.index(c1, r1);
    m.springs.push_back(
        {i, j, (m.rest_position[j] - m.rest_position[i]).norm(), p.stiffness, p.damping, kind});
  };
  for (int r = 0; r < def.rows; ++r) {
    for (int c = 0; c < def.cols; ++c) {
      add(c, r, c + 1, r, def.structural, SpringKind::structural);
      add(c, r, c, r + 1, def.structural, SpringKind::structural);
      add(c, r, c + 1, r + 1, def.shear, SpringKind::shear);
      add(c + 1, r, c, r + 1, def.shear, SpringKind::shear);
      add(c, r, c + 2, r, def.bending, SpringKind::bending);
      add(c, r, c, r + 2, def.bending, SpringKind::bending);
    }
  }

  // Two triangles per quad; (i, i + cols, i + 1) faces +z when vertical and +y when horizontal.
  for (int r = 0; r + 1 < def.rows; ++r) {
    for (int c = 0; c + 1 < def.cols; ++c) {
      const int32_t i = m.index(c, r), right = i + 1, below = i + def.cols;
      m.triangles.push_back({i, below, right});
      m.triangles.push_back({right, below, below + 1});
    }
  }
  m.grid_triangles = true;
  finish(m);
  return m;
}

}  // namespace drape::model
