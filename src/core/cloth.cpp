#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "drape/cloth.h"
#include "parallel.h"

namespace drape {

const char* to_string(SpringKind k) {
  switch (k) {
    case SpringKind::structural: return "structural";
    case SpringKind::shear: return "shear";
    case SpringKind::bending: return "bending";
  }
  return "?";
}

namespace {

// splitmix64: a tiny, well-mixed hash so the perturbation depends on the index alone.
uint64_t mix(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform in [-1, 1), from the particle index.
double jitter(int64_t index) {
  return static_cast<double>(mix(static_cast<uint64_t>(index)) >> 11) * 0x1.0p-52 - 1.0;
}

// Greedy edge colouring: each spring takes the smallest colour that neither end uses yet.
// A grid needs about 14 colours. Springs are then stably sorted by colour.
void colour_springs(int32_t particles, std::vector<Spring>& springs,
                    std::vector<int32_t>& colour_begin) {
  std::vector<uint64_t> used(particles, 0);
  std::vector<int> colour(springs.size());
  int colours = 0;
  for (size_t s = 0; s < springs.size(); ++s) {
    const uint64_t taken = used[springs[s].i] | used[springs[s].j];
    int c = 0;
    while (c < 63 && (taken >> c & 1u)) ++c;
    colour[s] = c;  // colour 63 is a shared overflow; never reached by grids or sane meshes
    used[springs[s].i] |= uint64_t{1} << c;
    used[springs[s].j] |= uint64_t{1} << c;
    colours = std::max(colours, c + 1);
  }
  std::vector<Spring> sorted;
  sorted.reserve(springs.size());
  colour_begin.assign(1, 0);
  for (int c = 0; c < colours; ++c) {
    for (size_t s = 0; s < springs.size(); ++s)
      if (colour[s] == c) sorted.push_back(springs[s]);
    colour_begin.push_back(static_cast<int32_t>(sorted.size()));
  }
  springs = std::move(sorted);
}

}  // namespace

ClothModel build_grid(const ClothDef& def) {
  ClothModel m;
  m.cols = def.cols;
  m.rows = def.rows;
  const int32_t n = def.cols * def.rows;
  const double dx = def.width / (def.cols - 1);
  const double dy = def.height / (def.rows - 1);
  // Unit vectors along the columns and the rows.
  const Vec3 across(1.0, 0.0, 0.0);
  const Vec3 down =
      def.orientation == Orientation::vertical ? Vec3(0.0, -1.0, 0.0) : Vec3(0.0, 0.0, 1.0);

  m.rest_position.resize(n);
  m.uv.resize(n);
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
  colour_springs(n, m.springs, m.colour_begin);

  // Two triangles per quad; (i, i + cols, i + 1) faces +z when vertical and +y when horizontal.
  for (int r = 0; r + 1 < def.rows; ++r) {
    for (int c = 0; c + 1 < def.cols; ++c) {
      const int32_t i = m.index(c, r), right = i + 1, below = i + def.cols;
      m.triangles.push_back({i, below, right});
      m.triangles.push_back({right, below, below + 1});
    }
  }
  m.grid_triangles = true;
  m.vertex_triangle_begin.assign(n + 1, 0);
  for (const Triangle& t : m.triangles)
    for (int32_t p : t) ++m.vertex_triangle_begin[p + 1];
  for (int32_t p = 0; p < n; ++p) m.vertex_triangle_begin[p + 1] += m.vertex_triangle_begin[p];
  m.vertex_triangles.resize(m.triangles.size() * 3);
  std::vector<int32_t> fill(m.vertex_triangle_begin.begin(), m.vertex_triangle_begin.end() - 1);
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (int32_t p : m.triangles[t]) m.vertex_triangles[fill[p]++] = static_cast<int32_t>(t);
  return m;
}

ClothState initial_state(const ClothDef& def, const ClothModel& model) {
  const int32_t n = model.size();
  ClothState s;
  s.x = model.rest_position;
  s.v.assign(n, Vec3::Zero());
  s.inv_mass.resize(n);
  for (int32_t i = 0; i < n; ++i) s.inv_mass[i] = 1.0 / model.mass[i];
  s.pinned.assign(n, 0);
  s.anchor.assign(n, Vec3::Zero());
  for (const Pin& p : def.pins) {
    const int32_t i = model.index(p.col < 0 ? p.col + model.cols : p.col,
                                  p.row < 0 ? p.row + model.rows : p.row);
    s.pinned[i] = 1;
    s.inv_mass[i] = 0.0;
  }
  const Vec3 out_of_plane =
      def.orientation == Orientation::vertical ? Vec3(0.0, 0.0, 1.0) : Vec3(0.0, 1.0, 0.0);
  for (int32_t i = 0; i < n; ++i) {
    if (!s.pinned[i]) s.x[i] += def.perturbation * jitter(i) * out_of_plane;
    s.anchor[i] = s.x[i];
  }
  s.normal.assign(n, Vec3::Zero());
  s.area.assign(n, 0.0);
  update_normals(model, s);
  return s;
}

std::vector<double> spring_sums(const ClothModel& model, double Spring::*field) {
  std::vector<double> sum(model.size(), 0.0);
  for (const Spring& s : model.springs) {
    sum[s.i] += s.*field;
    sum[s.j] += s.*field;
  }
  return sum;
}

namespace {

// A triangle's cross product, its normal times twice its area, and that length.
struct Face {
  Vec3 cross;
  double twice_area;
};

inline Face face(const std::vector<Vec3>& x, const Triangle& t) {
  const Vec3 cross = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
  return {cross, cross.norm()};
}

// Summing a particle's faces' cross products weights their normals by area; the particle owns a
// third of each triangle.
struct FaceSum {
  Vec3 cross = Vec3::Zero();
  double twice_area = 0.0;

  void add(const Face& f) {
    cross += f.cross;
    twice_area += f.twice_area;
  }
  void store(ClothState& s, int32_t p) const {
    const double len = cross.norm();
    s.area[p] = twice_area / 6.0;
    s.normal[p] = len > 0.0 ? Vec3(cross * (1.0 / len)) : Vec3::Zero();
  }
};

// Any triangles: each particle gathers its own (no scatter), so any thread count gives the
// same bits; every face is computed once per corner.
void gather_normals(const ClothModel& model, ClothState& state) {
  const int32_t n = model.size();
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t p = 0; p < n; ++p) {
    FaceSum sum;
    for (int32_t k = model.vertex_triangle_begin[p]; k < model.vertex_triangle_begin[p + 1]; ++k)
      sum.add(face(state.x, model.triangles[model.vertex_triangles[k]]));
    sum.store(state, p);
  }
}

// build_grid's triangles: every face once. Row r's particles lie on the quads of rows r − 1
// and r, whose faces a thread keeps from one row to the next (two rows of them, per thread);
// each particle sums its faces in the order of their index, as gather_normals does.
void grid_normals(const ClothModel& m, ClothState& s) {
  const int quads = m.cols - 1;  // per row of quads, each two faces: (i, below, right) first
#pragma omp parallel if (worth_threads(m.size()))
  {
    thread_local std::vector<Face> faces;
    faces.resize(4 * static_cast<size_t>(quads));
    Face *above = faces.data(), *below = above + 2 * quads;
    int below_row = -2;  // the row of quads `below` holds
    auto fill = [&](int q, Face* f) {
      for (int k = 0; k < 2 * quads; ++k) f[k] = face(s.x, m.triangles[2 * q * quads + k]);
    };
#pragma omp for schedule(static)
    for (int r = 0; r < m.rows; ++r) {
      if (below_row == r - 1) {
        std::swap(above, below);
      } else if (r > 0) {
        fill(r - 1, above);
      }
      if (r + 1 < m.rows) fill(r, below);
      below_row = r;
      for (int c = 0; c < m.cols; ++c) {
        FaceSum sum;
        if (r > 0) {
          if (c > 0) sum.add(above[2 * c - 1]);
          if (c < quads) {
            sum.add(above[2 * c]);
            sum.add(above[2 * c + 1]);
          }
        }
        if (r + 1 < m.rows) {
          if (c > 0) {
            sum.add(below[2 * c - 2]);
            sum.add(below[2 * c - 1]);
          }
          if (c < quads) sum.add(below[2 * c]);
        }
        sum.store(s, m.index(c, r));
      }
    }
  }
}

}  // namespace

void update_normals(const ClothModel& model, ClothState& state) {
  if (model.grid_triangles) {
    grid_normals(model, state);
  } else {
    gather_normals(model, state);
  }
}

int64_t heap_bytes(const ClothModel& m) {
  return heap_bytes(m.springs, m.colour_begin, m.triangles, m.vertex_triangle_begin,
                    m.vertex_triangles, m.uv, m.rest_position, m.mass);
}

int64_t heap_bytes(const ClothState& s) {
  return heap_bytes(s.x, s.v, s.inv_mass, s.pinned, s.anchor, s.normal, s.area);
}

}  // namespace drape
