// Building a cloth's model: the generators (grid, mesh), the checks a mesh must pass, the spring
// colouring and the geodesic distances the long-range attachments use. Private to the core.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "drape/cloth.h"
#include "drape/mesh.h"
#include "drape/scene.h"

namespace drape::model {

/// The grid generator: build_grid's particles (equal masses), the seed's three spring kinds,
/// two triangles per quad, uv and the GridTopology.
ClothModel grid(const ClothDef& def);

/// A cloth from def.mesh placed by def.transform: a structural spring on every edge, a bending
/// spring across every edge two triangles share, masses by area, the mesh's own uv.
ClothModel from_mesh(const ClothDef& def);

/// Derives the model's masses, spring stiffness and damping and bending elements from a
/// material (model/material.cpp says how), replacing the seed's bending springs, and recolours
/// the springs. Called by build_model after the generator.
void apply_material(const MaterialDef& material, ClothModel& m);

/// The least share of a grid's warp and weft stretch its threads (structural springs) carry
/// themselves; the diagonals carry the rest, and with it the shear.
inline constexpr double kThreadShare = 0.5;

/// The shear stiffness (N/m) a grid of dx × dy cells gives `material`: its own, or less where
/// the diagonals that carry it would leave the threads under kThreadShare of the stretch. A
/// grid's diagonals stiffen warp and weft too (model/material.cpp), and where they carry all of
/// both, the sheet has a mode that costs no energy: warp stretched as weft shortens.
double grid_shear(const MaterialDef& material, double dx, double dy);

/// Throws InputError at `path` naming the first problem that stops `mesh` from being a cloth:
/// no triangles, an index out of range, a non-finite coordinate, a vertex in no triangle, a
/// triangle of zero area, an edge shared by more than two triangles. Triangles are named by
/// their file line when the mesh has them.
void check_mesh(const ClothMesh& mesh, const std::string& path);

/// What every generator finishes with: the triangles around each particle, the springs
/// coloured (colour_springs), the mean structural rest length and a fresh id.
void finish(ClothModel& m);

/// Greedy edge colouring: each spring takes the smallest colour that neither end has yet, and
/// the springs are stably sorted by colour. A spring that finds none of the first 63 free goes
/// to a last colour processed by one thread (ClothModel::independent_colours): a grid needs
/// about 14 colours, a vertex of valence over 63 (the centre of a fine fan) more.
void colour_springs(int32_t particles, std::vector<Spring>& springs,
                    std::vector<int32_t>& colour_begin, int& independent_colours);

/// For every particle, the `k` of `sources` nearest to it along the cloth's rest shape (fewer
/// where fewer reach it), with their geodesic distances: nearest_source[p·k + t] and
/// distance[p·k + t] for t < k, sorted by source, −1 where none. Distances are Dijkstra's over
/// the triangles' edges improved by an unfolding through each triangle (a virtual source: the
/// point at distance d_a and d_b from two corners whose distances are known), so that they are
/// the straight line across a flat cloth and along the surface of a developable one (a tube);
/// on a curved one within about an edge length.
void nearest_sources(const ClothModel& model, const std::vector<int32_t>& sources, int k,
                     std::vector<int32_t>& nearest_source, std::vector<double>& distance);

}  // namespace drape::model
