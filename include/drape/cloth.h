// The cloth: its fixed set-up (ClothModel: springs, triangles, masses), built once from a grid
// or any triangle mesh, and its running state (ClothState: positions, velocities, pins).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "drape/math.h"
#include "drape/mesh.h"
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

/// An isometric bending element (Bergou, Wardetzky, Harmon, Zorin & Grinspun 2006, "A quadratic
/// bending model for inextensible surfaces") across an edge two triangles share: the curvature
/// vector c = Σ_k w_k·x_{v_k} (zero while the pair lies flat) and the energy ½·stiffness·|c|²,
/// quadratic in the positions, so its Hessian is the constant stiffness·w·wᵀ ⊗ I.
struct BendingElement {
  std::array<int32_t, 4> v{};  ///< the edge's two ends, then the two far corners
  std::array<double, 4> w{};   ///< weights (cotangents of the rest triangles' angles), sum 0
  double stiffness = 0.0;      ///< N/m, k of ½k|c|², from the rigidity B and the rest areas
  double damping = 0.0;        ///< N·s/m, c of the damping force −c·w_k·Σ_l w_l·v_l on v_k
};

/// The row/column layout of a cloth built by the grid generator, which fast paths may use
/// (xpbd's line passes); every path also works without it. Particle (col, row) is
/// row·cols + col. Absent (cols = rows = 0) for a mesh.
struct GridTopology {
  int cols = 0;
  int rows = 0;
  bool present() const { return cols > 0; }
  int32_t index(int col, int row) const { return row * cols + col; }
};

/// What does not change while the cloth moves.
struct ClothModel {
  GridTopology grid;  ///< present when the grid generator built the cloth
  /// Springs grouped by colour: no two springs of one of the first `independent_colours`
  /// colours share a particle, so each of those can be processed in parallel without atomics
  /// and in a fixed order (deterministic results for any thread count). Colour c holds springs
  /// [colour_begin[c], colour_begin[c + 1]). A last colour past them, if any, holds the
  /// springs greedy colouring could not place (around a vertex of very high valence): it must
  /// be processed by one thread (colour_is_independent).
  std::vector<Spring> springs;
  std::vector<int32_t> colour_begin;
  int independent_colours = 0;
  std::vector<Triangle> triangles;  ///< counter-clockwise seen from the front
  /// The triangles are the grid generator's, two per quad in its order (update_normals then
  /// takes the grid's shortcut).
  bool grid_triangles = false;
  /// The triangles around each particle: particle p's are
  /// vertex_triangles[vertex_triangle_begin[p] .. vertex_triangle_begin[p + 1]).
  std::vector<int32_t> vertex_triangle_begin;
  std::vector<int32_t> vertex_triangles;
  /// Per particle, texture coordinates for drawing, v running down the texture: the grid's (u
  /// along the columns, v down the rows, in [0, 1]), a mesh's own (its first corner's at a
  /// seam), or, for a mesh without any, the rest shape projected on its widest plane.
  std::vector<Vec2> uv;
  bool has_texcoords = false;  ///< the mesh came with texture coordinates (or is a grid)
  /// A mesh's texture coordinates per triangle corner, as it had them (seams kept), for export;
  /// empty when `uv` holds them exactly (grids, meshes without seams) or there are none.
  std::vector<Vec2> texcoords;
  std::vector<Triangle> triangle_texcoords;
  /// Bending elements (cloth.material only; the seed's model bends by springs).
  std::vector<BendingElement> bending;
  /// Factor on the stiffness of a compressed spring (cloth.material's compression; 1 for the
  /// seed's model): compressed cloth yields and buckles instead of resisting as in tension.
  double compression = 1.0;
  bool material = false;  ///< built from cloth.material (bending elements, masses by density)
  std::vector<Vec3> rest_position;  ///< m, the rest shape (before the perturbation)
  std::vector<double> mass;         ///< kg per particle
  double mean_edge = 0.0;           ///< m, mean rest length of the structural springs
  uint64_t id = 0;  ///< different for every model built (so a drawing knows when to upload)

  int32_t size() const { return static_cast<int32_t>(mass.size()); }
  int32_t index(int col, int row) const { return grid.index(col, row); }
  int colours() const { return static_cast<int>(colour_begin.size()) - 1; }
  bool colour_is_independent(int c) const { return c < independent_colours; }
};

/// What changes while the cloth moves.
struct ClothState {
  std::vector<Vec3> x;           ///< m, positions
  std::vector<Vec3> v;           ///< m/s, velocities
  std::vector<double> inv_mass;  ///< 1/kg; 0 for a pinned or held particle
  std::vector<uint8_t> pinned;   ///< 1 where a pin holds the particle at `anchor`
  std::vector<Vec3> anchor;      ///< m, where each pinned particle is held
  std::vector<Vec3> normal;      ///< unit, area-weighted vertex normals
  std::vector<double> area;      ///< m², a third of the adjacent triangles' areas
};

/// Builds the cloth `def` describes: the grid's particles, springs (structural, shear,
/// bending), triangles and uv, or a mesh's (def.mesh, placed by def.transform) with its
/// structural and bending springs and masses by area. `def` must have passed check(); a
/// problem only the built cloth shows (a pin box holding no vertex) throws InputError.
ClothModel build_model(const ClothDef& def);

/// The start state: the rest shape plus the deterministic perturbation along the rest normals,
/// at rest, pins applied. Throws InputError for a pin that names no particle.
ClothState initial_state(const ClothDef& def, const ClothModel& model);

/// The particles `def.pins` name on `model`, in increasing order without repeats. Throws
/// InputError naming the pin ("cloth.pins[k]") when one names no particle.
std::vector<int32_t> pinned_particles(const ClothDef& def, const ClothModel& model);
/// The particles pin entry def.pins[k] names, in increasing order. Throws as pinned_particles.
std::vector<int32_t> pin_particles(const ClothDef& def, const ClothModel& model, size_t k);

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
