#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "drape/cloth.h"
#include "drape/error.h"
#include "model/model.h"
#include "parallel.h"
#include "random.h"

namespace drape {

const char* to_string(SpringKind k) {
  switch (k) {
    case SpringKind::structural:
      return "structural";
    case SpringKind::shear:
      return "shear";
    case SpringKind::bending:
      return "bending";
  }
  return "?";
}

ClothModel build_model(const ClothDef& def) {
  ClothModel m = def.mesh ? model::from_mesh(def) : model::grid(def);
  if (def.material) model::apply_material(*def.material, m);
  return m;
}

std::vector<int32_t> pinned_particles(const ClothDef& def, const ClothModel& model) {
  std::vector<int32_t> out;
  for (size_t k = 0; k < def.pins.size(); ++k) {
    const std::vector<int32_t> some = pin_particles(def, model, k);
    out.insert(out.end(), some.begin(), some.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int32_t> pin_particles(const ClothDef& def, const ClothModel& model, size_t k) {
  std::vector<int32_t> out;
  {
    const Pin& p = def.pins[k];
    const std::string path = "cloth.pins[" + std::to_string(k) + "]";
    switch (p.kind) {
      case PinKind::grid: {
        const GridTopology& g = model.grid;
        if (!g.present())
          throw InputError(path,
                           "a grid index or corner name needs a grid cloth; pin a mesh "
                           "by {\"vertex\": i}, {\"box\": {\"min\": [...], \"max\": [...]}} or "
                           "{\"ball\": {\"center\": [...], \"radius\": r}}");
        out.push_back(
            g.index(p.col < 0 ? p.col + g.cols : p.col, p.row < 0 ? p.row + g.rows : p.row));
        break;
      }
      case PinKind::vertex:
        if (p.vertex < 0 || p.vertex >= model.size())
          throw InputError(path + ".vertex", "is " + std::to_string(p.vertex) +
                                                 ", but the cloth has " +
                                                 std::to_string(model.size()) + " vertices (0 to " +
                                                 std::to_string(model.size() - 1) + ")");
        out.push_back(p.vertex);
        break;
      case PinKind::box:
      case PinKind::ball: {
        const bool box = p.kind == PinKind::box;
        for (int32_t i = 0; i < model.size(); ++i) {
          const Vec3& x = model.rest_position[i];
          if (box ? (x.array() >= p.box_min.array()).all() && (x.array() <= p.box_max.array()).all()
                  : (x - p.ball_center).norm() <= p.ball_radius)
            out.push_back(i);
        }
        if (out.empty()) {
          Vec3 lo = model.rest_position[0], hi = lo;
          for (const Vec3& x : model.rest_position) {
            lo = lo.cwiseMin(x);
            hi = hi.cwiseMax(x);
          }
          char problem[320];
          std::snprintf(problem, sizeof problem,
                        "holds no vertex of the cloth (the cloth spans [%.4g, %.4g, %.4g] to "
                        "[%.4g, %.4g, %.4g] at the start)",
                        lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
          throw InputError(path + (box ? ".box" : ".ball"), problem);
        }
        break;
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
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
  for (const int32_t i : pinned_particles(def, model)) {
    s.pinned[i] = 1;
    s.inv_mass[i] = 0.0;
  }
  // The perturbation moves each free particle along its rest normal (out of a flat cloth's
  // plane) by up to perturbation × the mean edge length.
  s.normal.assign(n, Vec3::Zero());
  s.area.assign(n, 0.0);
  update_normals(model, s);
  const double amplitude = def.perturbation * model.mean_edge;
  for (int32_t i = 0; i < n; ++i) {
    if (!s.pinned[i]) s.x[i] += amplitude * uniform_from(static_cast<uint64_t>(i)) * s.normal[i];
    s.anchor[i] = s.x[i];
  }
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

// Any triangles: each particle gathers its own (no scatter), so any thread count gives the
// same bits; every face is computed once per corner. Each cross product is the triangle's
// normal times twice its area: summing them weights by area; the particle owns a third of each
// triangle.
void gather_normals(const ClothModel& model, ClothState& state) {
  const int32_t n = model.size();
#pragma omp parallel for schedule(static) if (worth_threads(n))
  for (int32_t p = 0; p < n; ++p) {
    Vec3 sum = Vec3::Zero();
    double twice_area = 0.0;
    for (int32_t k = model.vertex_triangle_begin[p]; k < model.vertex_triangle_begin[p + 1]; ++k) {
      const Triangle& t = model.triangles[model.vertex_triangles[k]];
      const Vec3 cross = (state.x[t[1]] - state.x[t[0]]).cross(state.x[t[2]] - state.x[t[0]]);
      sum += cross;
      twice_area += cross.norm();
    }
    const double len = sum.norm();
    state.area[p] = twice_area / 6.0;
    state.normal[p] = len > 0.0 ? Vec3(sum * (1.0 / len)) : Vec3::Zero();
  }
}

// build_grid's triangles: every face once. Row r's particles lie on the quads of rows r − 1
// and r, whose faces a thread keeps from one row to the next (two rows of them, per thread, as
// arrays of numbers so that the loops vectorise). Each particle sums its faces in the order of
// their index, as gather_normals does; a row's missing neighbours (its ends, and the rows past
// the cloth's edges) read as zero faces, which change no sum.
void grid_normals(const ClothModel& m, ClothState& s) {
  const int cols = m.grid.cols, quads = cols - 1;
  // A row of quads: for each of its two faces (i, below, right) and (right, below, below + 1),
  // the cross product's x, y, z and its length, each an array of quads + 2 numbers whose first
  // and last are the zero faces left and right of the row.
  constexpr int kArrays = 8;
  const int span = quads + 2;
  const double* x = s.x.data()->data();  // Vec3 holds its three numbers contiguously
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
#pragma omp parallel if (worth_threads(m.size()))
  {
    // Zeroed when its size changes only: the zero faces and the zero row are never written.
    // A team's threads live on from one parallel region to the next, so after the first call
    // (initial_state's) stepping allocates nothing here.
    thread_local std::vector<double> faces;
    const size_t size = 3 * kArrays * static_cast<size_t>(span);
    if (faces.size() != size) faces.assign(size, 0.0);
    double *above = faces.data(), *below = above + kArrays * span;
    const double* none = below + kArrays * span;  // a row of zero faces
    int below_row = -2;                           // the row of quads `below` holds
    auto fill = [&](int q, double* f) {
      double* out[kArrays];
      for (int a = 0; a < kArrays; ++a) out[a] = f + a * span + 1;
      const double* top = x + 3 * static_cast<size_t>(q) * cols;
      const double* bottom = top + 3 * cols;
#pragma omp simd
      for (int c = 0; c < quads; ++c) {
        const double* i = top + 3 * c;  // (c, q); right: i + 3; below: bottom + 3c
        const double* d = bottom + 3 * c;
        // (i, below, right): (below − i) × (right − i).
        const double ux = d[0] - i[0], uy = d[1] - i[1], uz = d[2] - i[2];
        const double vx = i[3] - i[0], vy = i[4] - i[1], vz = i[5] - i[2];
        const double ax = uy * vz - uz * vy, ay = uz * vx - ux * vz, az = ux * vy - uy * vx;
        // (right, below, below + 1): (below − right) × (below + 1 − right).
        const double px = d[0] - i[3], py = d[1] - i[4], pz = d[2] - i[5];
        const double qx = d[3] - i[3], qy = d[4] - i[4], qz = d[5] - i[5];
        const double bx = py * qz - pz * qy, by = pz * qx - px * qz, bz = px * qy - py * qx;
        out[0][c] = ax;
        out[1][c] = ay;
        out[2][c] = az;
        out[3][c] = std::sqrt(ax * ax + ay * ay + az * az);
        out[4][c] = bx;
        out[5][c] = by;
        out[6][c] = bz;
        out[7][c] = std::sqrt(bx * bx + by * by + bz * bz);
      }
    };
#pragma omp for schedule(static)
    for (int r = 0; r < m.grid.rows; ++r) {
      if (below_row == r - 1) {
        std::swap(above, below);
      } else if (r > 0) {
        fill(r - 1, above);
      }
      if (r + 1 < m.grid.rows) fill(r, below);
      below_row = r;
      // Particle c's faces, by index: the upper row's second face of quad c − 1, both of quad c;
      // the lower row's both of quad c − 1, first of quad c. Slot c + 1 of an array is quad c.
      const double* up = r > 0 ? above : none;
      const double* down = r + 1 < m.grid.rows ? below : none;
      Vec3* normal = s.normal.data() + static_cast<size_t>(r) * cols;
      double* area = s.area.data() + static_cast<size_t>(r) * cols;
#pragma omp simd
      for (int c = 0; c < cols; ++c) {
        double sum[4];
        for (int k = 0; k < 4; ++k) {
          // [0]: quad c − 1, [1]: quad c; a, b the upper row's first and second faces, e, f
          // the lower row's.
          const double *a = up + k * span + c, *b = up + (4 + k) * span + c;
          const double *e = down + k * span + c, *f = down + (4 + k) * span + c;
          sum[k] = 0.0 + b[0] + a[1] + b[1] + e[0] + f[0] + e[1];
        }
        const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        const double inv = len > 0.0 ? 1.0 / len : 0.0;
        area[c] = sum[3] / 6.0;
        normal[c] = Vec3(sum[0] * inv, sum[1] * inv, sum[2] * inv);
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
  return heap_bytes(m.springs, m.bending, m.colour_begin, m.triangles, m.vertex_triangle_begin,
                    m.vertex_triangles, m.uv, m.texcoords, m.triangle_texcoords, m.rest_position,
                    m.mass);
}

int64_t heap_bytes(const ClothState& s) {
  return heap_bytes(s.x, s.v, s.inv_mass, s.pinned, s.anchor, s.normal, s.area);
}

}  // namespace drape
