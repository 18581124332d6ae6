// A path cover of a mesh's edges for xpbd's line passes on any mesh: the edges split into
// chains (paths) that run as straight as the mesh allows, the chains into a few layers
// ("forests") whose chains share no particle, so that every chain of a layer can be solved at
// once, exactly, as the grid solves its rows and columns. On a grid-like mesh the layers are its
// rows and columns (and its diagonals); on any mesh each layer removes a stretch along whole
// chains at once.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "drape/math.h"

namespace drape::xpbd {

struct ChainCover {
  /// layers[f] holds chains of particles; no particle is in two chains of one layer.
  std::vector<std::vector<std::vector<int32_t>>> layers;
  /// The edges (indices into the edges given) in no chain: to be swept one by one.
  std::vector<int32_t> left_over;
};

/// Covers `edges` (particle pairs of the rest shape `x`) with chains in at most `max_layers`
/// layers, none shorter than `min_length` edges. At each particle its edges are paired most
/// opposite first (a chain continues as straight as it can, never turning by more than 60°);
/// the paired edges form trails, longest first, each laid whole into the first layer where all
/// its particles are free (so a grid-like mesh's rows fill one layer and its columns the next),
/// or else cut into the runs each layer has room for. Deterministic.
ChainCover cover_with_chains(const std::vector<Vec3>& x,
                             const std::vector<std::pair<int32_t, int32_t>>& edges,
                             int max_layers, int min_length);

}  // namespace drape::xpbd
