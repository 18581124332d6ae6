// The cloth: its fixed set-up (ClothModel: springs, triangles, masses) and its running state
// (ClothState: positions, velocities, pins). Set-up is built once; stepping changes the state.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "drape/math.h"
#include "drape/scene.h"

namespace drape {

/// What a spring stands for in the grid (see ClothDef): structural (right and lower neighbour),
/// shear (quad diagonals), bending (two steps right and two down).
enum class SpringKind : uint8_t { structural, shear, bending };
inline constexpr int kSpringKinds = 3;  ///< how many kinds there are
const char* to_string(SpringKind k);

/// A spring between particles i and j. Force on i: k(|d| − L)·d̂ + c((v_j − v_i)·d̂)·d̂ with
/// d = x_j − x_i; the opposite force acts on j.
struct Spring {
  int32_t i = 0;
  int32_t j = 0;
  double rest = 0.0;       ///< m, rest length L
  double stiffness = 0.0;  ///< N/m, k
  double damping = 0.0;    ///< N·s/m, c
  SpringKind kind = SpringKind::structural;
};

/// Three particle indices.
using Triangle = std::array<int32_t, 3>;

/// What does not change while the cloth moves.
struct ClothModel {
  int cols = 0;  ///< particles per row of the grid
  int rows = 0;  ///< particles per column of the grid
  /// Springs grouped by colour: no two springs of one colour share a particle, so each colour
  /// can be processed in parallel without atomics and in a fixed order (deterministic results
  /// for any thread count). Colour c holds springs [colour_begin[c], colour_begin[c + 1]).
  std::vector<Spring> springs;
  std::vector<int32_t> colour_begin;
  std::vector<Triangle> triangles;  ///< counter-clockwise seen from the front
  /// The triangles are build_grid's, two per quad in its order (update_normals then takes the
  /// grid's shortcut).
  bool grid_triangles = false;
  /// The triangles around each particle: particle p's are
  /// vertex_triangles[vertex_triangle_begin[p] .. vertex_triangle_begin[p + 1]).
  std::vector<int32_t> vertex_triangle_begin;
  std::vector<int32_t> vertex_triangles;
  std::vector<Vec2> uv;             ///< texture coordinates in [0, 1]², u along the columns
  std::vector<Vec3> rest_position;  ///< m, the flat grid before perturbation
  std::vector<double> mass;         ///< kg per particle

  int32_t size() const { return static_cast<int32_t>(mass.size()); }
  int32_t index(int col, int row) const { return row * cols + col; }
  int colours() const { return static_cast<int>(colour_begin.size()) - 1; }
};

/// What changes while the cloth moves.
struct ClothState {
  std::vector<Vec3> x;            ///< m, positions
  std::vector<Vec3> v;            ///< m/s, velocities
  std::vector<double> inv_mass;   ///< 1/kg; 0 for a pinned or held particle
  std::vector<uint8_t> pinned;    ///< 1 where a pin holds the particle at `anchor`
  std::vector<Vec3> anchor;       ///< m, where each pinned particle is held
  std::vector<Vec3> normal;       ///< unit, area-weighted vertex normals
  std::vector<double> area;       ///< m², a third of the adjacent triangles' areas
};

/// Builds the grid's particles, springs (structural, shear, bending), triangles and uv.
/// `def` must have passed check().
ClothModel build_grid(const ClothDef& def);

/// The start state: the flat grid plus the deterministic perturbation, at rest, pins applied.
ClothState initial_state(const ClothDef& def, const ClothModel& model);

/// Recomputes state.normal and state.area from state.x.
void update_normals(const ClothModel& model, ClothState& state);

/// Heap bytes held by vectors (their capacity), for memory reports: heap_bytes(a, b, ...).
template <typename T, typename Alloc>
int64_t heap_bytes(const std::vector<T, Alloc>& v) {
  return static_cast<int64_t>(v.capacity() * sizeof(T));
}
template <typename First, typename Second, typename... Rest>
int64_t heap_bytes(const First& first, const Second& second, const Rest&... rest) {
  return heap_bytes(first) + heap_bytes(second, rest...);
}
/// Heap bytes of the model's arrays (springs, triangles, adjacency, rest shape, masses).
int64_t heap_bytes(const ClothModel& model);
/// Heap bytes of the state's arrays.
int64_t heap_bytes(const ClothState& state);

/// Per particle, the sum of one spring field over the springs that touch it, e.g.
/// spring_sums(model, &Spring::stiffness): the total stiffness at each particle (stability
/// bounds and convergence estimates use it).
std::vector<double> spring_sums(const ClothModel& model, double Spring::*field);

}  // namespace drape
