// The cloth passing through itself: how many of its triangles cross one another. A measurement,
// not a response: it tells a user (and every test of self-collision to come) how far a state is
// from one a real cloth could reach.
#pragma once

#include <cstdint>
#include <vector>

#include "drape/math.h"
#include "drape/mesh.h"

namespace drape {

/// The number of pairs of `triangles` (corners indexing `positions`) that share no vertex and
/// cross: an edge of one passes through the inside of the other. Each pair counts once.
///
/// Touching is not crossing: a pair whose only contact is a corner or an edge lying on the
/// other triangle's plane or edge, or two triangles overlapping in one plane, is not counted,
/// nor is a pair whose crossing is within the rounding error of the orientation test (its
/// sign is used only where Shewchuk's error bound certifies it), so a count is never raised by
/// rounding. Triangles with a non-finite corner (a diverged state) are left out.
///
/// Broad phase: a uniform grid of cells about one triangle wide, each triangle's bounding box
/// entered in the cells it overlaps, so the work grows with the triangles and the pairs that
/// share a cell, not with their square. Runs on OpenMP threads for large cloths; the count is
/// the same for any thread count.
int64_t count_self_intersections(const std::vector<Triangle>& triangles,
                                 const std::vector<Vec3>& positions);

}  // namespace drape
