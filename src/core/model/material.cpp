// A material turned into the model's numbers: masses by area, stretch and shear springs whose
// stiffness comes from the sheet's, and isometric bending elements from the rigidity B.
//
// Why springs for stretch and shear rather than triangle membrane elements: every method
// (symplectic, implicit, fast's prefactored matrix, xpbd's colour sweeps and line passes) already
// solves springs, and on the grid the springs reproduce the sheet's small-strain stiffness
// exactly, as follows. A grid cell dx × dy holds one spring along each axis and two diagonals of
// length l = sqrt(dx² + dy²). Under a uniform strain ε its energy per area is
//   W = ½(k_u·dx/dy)ε_uu² + ½(k_v·dy/dx)ε_vv² + (k_d·l²/(dx·dy))·[((dx²ε_uu + dy²ε_vv)/l²)²
//       + (2·dx·dy·ε_uv/l²)²],
// so the shear stiffness (W = ½Gγ², γ = 2ε_uv) is G = 2k_d·dx·dy/l², and the diagonals add
// G·dx²/dy² to the warp stiffness and G·dy²/dx² to the weft's. Choosing
//   k_d = G·l²/(2·dx·dy),  k_u = (S_warp − G·dx²/dy²)·dy/dx,  k_v = (S_weft − G·dy²/dx²)·dx/dy
// gives σ_uu/ε_uu = S_warp and σ_vv/ε_vv = S_weft (cross direction held) and shear G, at any
// resolution (springs along the border stand for half a strip and take half of k). Only the
// structural springs (the threads) soften in compression; shear keeps G both ways.
//
// The diagonals also couple warp and weft by G (a Poisson effect), so where G·dx²/dy² comes
// near S_warp (or G·dy²/dx² near S_weft) the threads carry nothing and warp stretched as weft
// shortens costs almost no energy: the knit (G 36.9 N/m, S_warp 16.6) stretched 11% along a
// hanging strip that way. Such a grid takes the largest G that leaves the threads kThreadShare
// of each stretch (grid_shear): its stretch stays the material's and its shear is softer.
//
// A mesh has one spring per edge: Van Gelder 1998 ("Approximate simulation of elastic membranes
// by triangulated spring meshes") gives edge e the stiffness k_e = E·(Σ areas of its
// triangles)/|e|², which is exact for the Young's modulus of an equilateral mesh (Poisson ratio
// 1/3 and shear 3E/8 then follow: edges alone cannot set shear apart). E is the stretch along
// the edge's direction in uv, S_warp·cos²θ + S_weft·sin²θ.
//
// Masses: each particle carries a third of its triangles' areas times the density, on grids as on
// meshes. Damping: stiffness-proportional (Rayleigh), c = β·k per spring and per bending
// element, so that it follows the material rather than the mesh.
#include <algorithm>
#include <cmath>
#include <map>

#include "model/model.h"

namespace drape::model {

namespace {

double cotangent(const Vec3& a, const Vec3& b) {
  return a.dot(b) / a.cross(b).norm();
}

// The edge direction's angle in the texture plane, as cos² and sin² of its angle from u.
std::pair<double, double> uv_direction(const ClothModel& m, int32_t i, int32_t j) {
  const Vec2 d = m.uv[j] - m.uv[i];
  const double len2 = d.squaredNorm();
  if (len2 == 0.0) return {0.5, 0.5};
  return {d.x() * d.x() / len2, d.y() * d.y() / len2};
}

}  // namespace

double grid_shear(const MaterialDef& mat, double dx, double dy) {
  const double threads =
      std::min(mat.stretch.x() * dy * dy / (dx * dx), mat.stretch.y() * dx * dx / (dy * dy));
  return std::min(mat.shear, (1.0 - kThreadShare) * threads);
}

void apply_material(const MaterialDef& mat, ClothModel& m) {
  const int32_t n = m.size();
  const std::vector<Vec3>& x = m.rest_position;

  // Masses by area, and each edge's triangle area for the mesh's springs.
  std::vector<double> area(n, 0.0);
  std::map<std::pair<int32_t, int32_t>, double> edge_area;
  for (const Triangle& t : m.triangles) {
    const double a = 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
    for (int k = 0; k < 3; ++k) {
      area[t[k]] += a / 3.0;
      const int32_t p = t[k], q = t[(k + 1) % 3];
      edge_area[{std::min(p, q), std::max(p, q)}] += a;
    }
  }
  for (int32_t i = 0; i < n; ++i) m.mass[i] = mat.density * area[i];

  // Stretch and shear springs; the seed's bending springs give way to bending elements.
  const double dx = m.grid.present() ? (x[1] - x[0]).norm() : 0.0;
  const double dy = m.grid.present() ? (x[m.grid.cols] - x[0]).norm() : 0.0;
  const double G = m.grid.present() ? grid_shear(mat, dx, dy) : mat.shear;
  std::vector<Spring> springs;
  springs.reserve(m.springs.size());
  for (Spring s : m.springs) {
    if (s.kind == SpringKind::bending) continue;
    if (m.grid.present()) {
      const bool along_u = std::abs(m.uv[s.j].y() - m.uv[s.i].y()) == 0.0;
      if (s.kind == SpringKind::shear) {
        s.stiffness = G * (dx * dx + dy * dy) / (2.0 * dx * dy);
      } else if (along_u) {
        s.stiffness = (mat.stretch.x() - G * dx * dx / (dy * dy)) * dy / dx;
      } else {
        s.stiffness = (mat.stretch.y() - G * dy * dy / (dx * dx)) * dx / dy;
      }
      // A spring along the cloth's edge stands for a strip half as wide.
      if (s.kind == SpringKind::structural) {
        const int ci = s.i % m.grid.cols, ri = s.i / m.grid.cols;
        const int cj = s.j % m.grid.cols, rj = s.j / m.grid.cols;
        const bool edge = along_u ? (ri == 0 || ri == m.grid.rows - 1) && ri == rj
                                  : (ci == 0 || ci == m.grid.cols - 1) && ci == cj;
        if (edge) s.stiffness *= 0.5;
      }
    } else {
      const auto [c2, s2] = uv_direction(m, s.i, s.j);
      const double E = mat.stretch.x() * c2 + mat.stretch.y() * s2;
      s.stiffness = E * edge_area[{std::min(s.i, s.j), std::max(s.i, s.j)}] / (s.rest * s.rest);
    }
    s.damping = mat.damping * s.stiffness;
    springs.push_back(s);
  }
  m.springs = std::move(springs);
  m.compression = mat.compression;
  m.material = true;

  // Isometric bending (Bergou et al. 2006) across every edge two triangles share. With the
  // weights w = (c₀₃ + c₀₄, c₀₁ + c₀₂, −c₀₁ − c₀₃, −c₀₂ − c₀₄) (cotangents of the rest angles at
  // the edge) and A the two triangles' area, ½·(B/A)·|Σ w_k x_k|² summed over the edges is
  // ½·B·∫κ² dA of a cylindrical bend on a regular grid (within the half cell the boundary edges
  // miss), so stiffness = B/A. B depends on the fold: an edge along direction θ in uv is a fold
  // line whose curvature runs across it, B = B_warp·sin²θ + B_weft·cos²θ.
  //
  // On a grid every quad is split along the same diagonal, and the elements of that one-sided
  // triangulation couple bending with twist: a clamped strip twisted and sagged about 20% more
  // than the elastica. The grid's elements are therefore built on both triangulations, each
  // with half the rigidity, whose biases cancel; a mesh's on its own triangles.
  m.bending.clear();
  std::vector<std::vector<Triangle>> triangulations{m.triangles};
  if (m.grid.present()) {
    std::vector<Triangle> other;
    for (int r = 0; r + 1 < m.grid.rows; ++r) {
      for (int c = 0; c + 1 < m.grid.cols; ++c) {
        const int32_t i = m.index(c, r), right = i + 1, below = i + m.grid.cols;
        other.push_back({i, below, below + 1});
        other.push_back({i, below + 1, right});
      }
    }
    triangulations.push_back(std::move(other));
  }
  const double share = 1.0 / static_cast<double>(triangulations.size());
  for (const std::vector<Triangle>& triangles : triangulations) {
    if (!(mat.bending.x() > 0.0 || mat.bending.y() > 0.0)) break;
    std::map<std::pair<int32_t, int32_t>, std::vector<int32_t>> edge_far;
    std::map<std::pair<int32_t, int32_t>, double> pair_area;
    for (const Triangle& t : triangles) {
      const double a = 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
      for (int k = 0; k < 3; ++k) {
        const int32_t p = t[k], q = t[(k + 1) % 3];
        const std::pair<int32_t, int32_t> e{std::min(p, q), std::max(p, q)};
        pair_area[e] += a;
        edge_far[e].push_back(t[(k + 2) % 3]);
      }
    }
    for (const auto& [e, far] : edge_far) {
      if (far.size() != 2) continue;
      BendingElement b;
      b.v = {e.first, e.second, far[0], far[1]};
      const Vec3 &x0 = x[b.v[0]], &x1 = x[b.v[1]], &x2 = x[b.v[2]], &x3 = x[b.v[3]];
      const Vec3 e0 = x1 - x0, e1 = x2 - x0, e2 = x3 - x0, e3 = x2 - x1, e4 = x3 - x1;
      const double c01 = cotangent(e0, e1), c02 = cotangent(e0, e2);
      const double c03 = cotangent(-e0, e3), c04 = cotangent(-e0, e4);
      b.w = {c03 + c04, c01 + c02, -c01 - c03, -c02 - c04};
      const auto [c2, s2] = uv_direction(m, e.first, e.second);
      const double B = mat.bending.x() * s2 + mat.bending.y() * c2;
      b.stiffness = share * B / pair_area[e];
      b.damping = mat.damping * b.stiffness;
      m.bending.push_back(b);
    }
  }
  colour_springs(n, m.springs, m.colour_begin, m.independent_colours);
}

}  // namespace drape::model
