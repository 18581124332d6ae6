// Meshes made in code: the shapes `drape mesh` writes to meshes/, and the benchmark's and the
// tests' irregular cloths.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "drape/mesh.h"
#include "random.h"

namespace drape::shapes {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Uniform in [-1, 1), from a seed and an index.
double uniform(uint64_t seed, uint64_t index) {
  return uniform_from(splitmix64(seed) ^ index);
}

// Turns every triangle to face `front` (the shapes below know where their front is).
template <class Front>
void orient(ClothMesh& m, Front front) {
  for (Triangle& t : m.triangles) {
    const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    if ((b - a).cross(c - a).dot(front((a + b + c) / 3.0)) < 0.0) std::swap(t[1], t[2]);
  }
}

// Per-vertex texture coordinates, one per vertex (no seams).
void vertex_texcoords(ClothMesh& m, const std::vector<Vec2>& uv) {
  m.texcoords = uv;
  m.triangle_texcoords = m.triangles;
}

// A quad (a, b, c, d) counter-clockwise as two triangles, split along a–c or b–d.
void quad(ClothMesh& m, int32_t a, int32_t b, int32_t c, int32_t d, bool other_diagonal) {
  if (other_diagonal) {
    m.triangles.push_back({a, b, d});
    m.triangles.push_back({b, c, d});
  } else {
    m.triangles.push_back({a, b, c});
    m.triangles.push_back({a, c, d});
  }
}

}  // namespace

ClothMesh disc(double radius, int rings, int first_ring, uint64_t seed) {
  ClothMesh m;
  std::vector<Vec2> uv;
  auto add = [&](double r, double angle) {
    const Vec3 p(r * std::cos(angle), 0.0, r * std::sin(angle));
    m.positions.push_back(p);
    uv.emplace_back(0.5 + 0.5 * p.x() / radius, 0.5 + 0.5 * p.z() / radius);
    return static_cast<int32_t>(m.positions.size() - 1);
  };
  add(0.0, 0.0);
  std::vector<int32_t> inner{0};
  std::vector<double> inner_angle{0.0};
  for (int k = 1; k <= rings; ++k) {
    // Ring k: first_ring·k vertices at jittered angles, rotated by a random offset, so that no
    // two rings line up and the strips between them triangulate irregularly.
    const int count = first_ring * k;
    const double step = kTwoPi / count, offset = step * 0.5 * (1.0 + uniform(seed, k));
    std::vector<int32_t> ring;
    std::vector<double> angle;
    for (int j = 0; j < count; ++j) {
      const double a = offset + step * (j + 0.3 * uniform(seed + 1, m.positions.size()));
      angle.push_back(a);
      ring.push_back(add(radius * k / rings, a));
    }
    if (k == 1) {
      for (int j = 0; j < count; ++j) m.triangles.push_back({0, ring[j], ring[(j + 1) % count]});
    } else {
      // Zip the two rings together by angle: a + b triangles, each with an edge on one ring.
      const int a = static_cast<int>(inner.size()), b = count;
      auto at = [](const std::vector<double>& ang, int i) {
        const int n = static_cast<int>(ang.size());
        return ang[i % n] + kTwoPi * (i / n);
      };
      int i = 0, j = 0;
      // Start both rings at their vertex nearest angle 0 going round: the lists are sorted.
      while (i < a || j < b) {
        const bool step_inner = j == b || (i < a && at(inner_angle, i + 1) < at(angle, j + 1));
        if (step_inner) {
          m.triangles.push_back({inner[i % a], inner[(i + 1) % a], ring[j % b]});
          ++i;
        } else {
          m.triangles.push_back({inner[i % a], ring[j % b], ring[(j + 1) % b]});
          ++j;
        }
      }
    }
    inner = ring;
    inner_angle = angle;
  }
  orient(m, [](const Vec3&) { return Vec3::UnitY(); });
  vertex_texcoords(m, uv);
  return m;
}

ClothMesh tube(double radius, double height, int around, int down) {
  ClothMesh m;
  for (int r = 0; r < down; ++r)
    for (int k = 0; k < around; ++k) {
      const double a = kTwoPi * k / around;
      m.positions.emplace_back(radius * std::cos(a), -height * r / (down - 1),
                               radius * std::sin(a));
    }
  // Texture coordinates with a seam (column `around` repeats column 0 at u = 1), v scaled as u
  // is so that the texture's squares stay square: u = 1 is once round.
  const double v_per_m = 1.0 / (kTwoPi * radius);
  for (int r = 0; r < down; ++r)
    for (int k = 0; k <= around; ++k)
      m.texcoords.emplace_back(static_cast<double>(k) / around,
                               1.0 - height * v_per_m * r / (down - 1));
  auto vertex = [&](int k, int r) { return r * around + k % around; };
  auto texcoord = [&](int k, int r) { return r * (around + 1) + k; };
  for (int r = 0; r + 1 < down; ++r)
    for (int k = 0; k < around; ++k) {
      m.triangles.push_back({vertex(k, r), vertex(k + 1, r), vertex(k + 1, r + 1)});
      m.triangle_texcoords.push_back({texcoord(k, r), texcoord(k + 1, r), texcoord(k + 1, r + 1)});
      m.triangles.push_back({vertex(k, r), vertex(k + 1, r + 1), vertex(k, r + 1)});
      m.triangle_texcoords.push_back({texcoord(k, r), texcoord(k + 1, r + 1), texcoord(k, r + 1)});
    }
  // Front outside; turning a triangle turns its texture corners with it.
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    Triangle& tri = m.triangles[t];
    const Vec3 &a = m.positions[tri[0]], &b = m.positions[tri[1]], &c = m.positions[tri[2]];
    const Vec3 centre = (a + b + c) / 3.0, out(centre.x(), 0.0, centre.z());
    if ((b - a).cross(c - a).dot(out) < 0.0) {
      std::swap(tri[1], tri[2]);
      std::swap(m.triangle_texcoords[t][1], m.triangle_texcoords[t][2]);
    }
  }
  return m;
}

ClothMesh flag(double width, double height, double notch, int cols, int rows) {
  // The fly edge at height y (0 at the top, −height at the bottom): the V notch's depth shrinks
  // to nothing at the top and bottom corners.
  auto fly_edge = [&](double y) {
    return width - notch * (1.0 - std::abs(y + 0.5 * height) / (0.5 * height));
  };
  ClothMesh m;
  std::vector<int32_t> index(static_cast<size_t>(cols) * rows, -1);
  std::vector<Vec2> uv;
  const double eps = 1e-9 * width;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x = width * c / (cols - 1), y = -height * r / (rows - 1);
      if (x > fly_edge(y) + eps) continue;
      index[r * cols + c] = static_cast<int32_t>(m.positions.size());
      m.positions.emplace_back(x, y, 0.0);
      uv.emplace_back(x / width, 1.0 + y / width);  // v up, both in units of the width
    }
  auto at = [&](int c, int r) { return index[r * cols + c]; };
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const int32_t a = at(c, r), b = at(c + 1, r), d = at(c, r + 1), e = at(c + 1, r + 1);
      const int kept = (a >= 0) + (b >= 0) + (d >= 0) + (e >= 0);
      if (kept == 4) {
        quad(m, a, d, e, b, false);
      } else if (kept == 3) {  // a corner cut by the notch: the three that are left
        Triangle t{};
        int k = 0;
        for (int32_t v : {a, d, e, b})
          if (v >= 0) t[k++] = v;
        m.triangles.push_back(t);
      }
    }
  // Drop the vertices that no triangle kept (alone on the notch's edge).
  std::vector<int32_t> renumber(m.positions.size(), -1);
  for (const Triangle& t : m.triangles)
    for (int32_t v : t) renumber[v] = 0;
  ClothMesh out;
  std::vector<Vec2> out_uv;
  for (size_t v = 0; v < m.positions.size(); ++v) {
    if (renumber[v] < 0) continue;
    renumber[v] = static_cast<int32_t>(out.positions.size());
    out.positions.push_back(m.positions[v]);
    out_uv.push_back(uv[v]);
  }
  for (Triangle t : m.triangles) {
    for (int32_t& v : t) v = renumber[v];
    out.triangles.push_back(t);
  }
  orient(out, [](const Vec3&) { return Vec3::UnitZ(); });
  vertex_texcoords(out, out_uv);
  return out;
}

ClothMesh jittered_grid(double size, int n, double jitter, uint64_t seed) {
  ClothMesh m;
  std::vector<Vec2> uv;
  const double spacing = size / (n - 1);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      double x = -0.5 * size + c * spacing, z = -0.5 * size + r * spacing;
      if (c > 0 && c + 1 < n && r > 0 && r + 1 < n) {
        const uint64_t i = static_cast<uint64_t>(r) * n + c;
        x += jitter * spacing * uniform(seed, 2 * i);
        z += jitter * spacing * uniform(seed, 2 * i + 1);
      }
      m.positions.emplace_back(x, 0.0, z);
      uv.emplace_back((x + 0.5 * size) / size, (z + 0.5 * size) / size);
    }
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const int32_t a = r * n + c;
      quad(m, a, a + n, a + n + 1, a + 1, uniform(seed + 7, a) < 0.0);
    }
  orient(m, [](const Vec3&) { return Vec3::UnitY(); });
  vertex_texcoords(m, uv);
  return m;
}

}  // namespace drape::shapes
