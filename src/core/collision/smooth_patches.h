// Smooth patches: parts of the cloth that cannot pass through themselves in a given state, so
// that self-collision's search may leave out the pairs inside them (Volino & Magnenat-Thalmann
// 1994, "Efficient self-collision detection on smoothly discretized surface animations using
// geometrical shape regularity").
//
// The patches are fixed once, from the rest shape: the pieces of the cloth that lie in one
// cube of a grid, the cubes' side doubling from level to level (an octree), so that each patch
// is part of one a level up, up to the cloth's connected pieces; the lowest level's cubes hold
// about kPatchTriangles. A patch may be found smooth only if it is a disk wound one way: every
// edge in at most two of its triangles, run in opposite directions where in two, one boundary
// loop, and V − E + F = 1.
//
// Such a patch is smooth in a state where every triangle's normal (by its winding) lies within
// kConeAngle of the patch's summed normal N, and its boundary loop, projected along N onto a
// plane, is a simple polygon. The projection is then one to one on the patch: each triangle
// projects keeping its orientation, so the patch's points over a point of the plane, each
// counted with its (positive) local degree, number the winding number of the projected
// boundary about it, which is 1 inside a simple polygon and 0 outside. So no two of its
// triangles that share no vertex meet. The tests err on the side of "not smooth": a normal or
// a boundary pair within rounding of the limit fails.
//
// The cone is narrower than the 90° the proof needs so that what the search leaves out inside a
// smooth patch is not a layer: its normals within 75° of N, a crease in it opens by 30° at the
// least, so that points on its two sides within a thickness (a quarter of an edge by default)
// of each other lie within about half an edge of the crease's line, neighbours; pairs within
// the search's reach inside a patch are otherwise neighbours pressed together along the cloth,
// which its springs resist, or the two edges of a gap in it closing in its plane.
//
// Each frame, the largest smooth patches (regions) are found from the top down, and a triangle
// is kept for the search only where its box shares a cell of a coarse grid with a triangle of
// another region or of no smooth patch; a vertex or an edge where one of its triangles is. A
// pair is left out only where all the triangles of both its elements lie in one region: so two
// triangles that cross, never in one region, leave their edge pair in the search.
// Two boxes that meet share a cell, so every pair the search would find between two regions,
// or with a part that is in none, is still found.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "box_grid.h"
#include "drape/cloth.h"

namespace drape {

class SmoothPatches {
 public:
  /// Splits the model's cloth (with its `edges`, as triangle_edges gives them) into patches.
  void prepare(const ClothModel& model, const std::vector<std::array<int32_t, 2>>& edges);

  /// Finds the regions with the particles at x.
  void update(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x);

  /// Decides what the search keeps, from the triangles' boxes (face_boxes[t] for the t with
  /// boxed[t], as wide as their vertices' and edges' boxes at least).
  void keep(const std::vector<Box>& face_boxes, const std::vector<uint8_t>& boxed);
  bool triangle_kept(int32_t t) const { return triangle_kept_[t]; }
  bool vertex_kept(int32_t p) const { return vertex_kept_[p]; }
  bool edge_kept(int32_t e) const { return edge_kept_[e]; }

  /// The region (smooth patch) of triangle t, or −1 where no smooth patch holds it.
  int32_t region_of_triangle(int32_t t) const { return region_[t]; }
  /// That of all of vertex p's (edge e's) triangles, or −1 where they lie in different ones or
  /// in none. (Not one triangle's: an edge on a region's border with a triangle of another
  /// region on its other side may be where those cross, and the search must see it.)
  int32_t region_of_vertex(int32_t p) const { return vertex_region_[p]; }
  int32_t region_of_edge(int32_t e) const { return edge_region_[e]; }
  /// Whether two elements of regions a and b lie in one smooth patch: no contact between them.
  static bool within_smooth(int32_t a, int32_t b) { return a == b && a >= 0; }

  /// Whether the last update found one region holding every triangle: then every pair of the
  /// cloth's elements lies inside it, none needs a search, and no two triangles meet.
  bool whole() const {
    return regions_ == 1 && in_regions_ == static_cast<int32_t>(region_.size());
  }

  /// The patches of the hierarchy and how many of them are disks.
  int32_t patches() const { return static_cast<int32_t>(nodes_.size()); }
  int32_t disks() const;
  /// How many regions the last update found, and the triangles in them.
  int32_t regions() const { return regions_; }
  int32_t triangles_in_regions() const { return in_regions_; }
  int64_t bytes() const;

  /// Triangles in a patch of the lowest level, about.
  static constexpr int32_t kPatchTriangles = 64;
  /// The widest angle between a triangle's normal and its patch's, degrees.
  static constexpr double kConeAngle = 75.0;

 private:
  struct Node {
    int32_t level = 0;
    int32_t begin = 0, end = 0;              ///< its triangles: levels_[level][begin .. end)
    int32_t loop_begin = 0, loop_end = 0;    ///< its boundary loop: loop_[..), empty: no disk
    int32_t child_begin = 0, child_end = 0;  ///< its patches one level down: children_[..)
  };
  /// Appends node's boundary loop to loop_ where its triangles make a disk wound one way.
  void find_loop(const std::vector<Triangle>& triangles, Node& node);
  bool smooth(const Node& node, const std::vector<Vec3>& x) const;

  std::vector<Node> nodes_;
  std::vector<std::vector<int32_t>> levels_;  ///< per level, the triangles patch by patch
  std::vector<int32_t> children_, roots_, loop_;
  std::vector<int32_t> side_;  ///< edge of triangle t's side k (from corner k): side_[3t + k]
  std::vector<int32_t> edge_begin_, edge_triangles_;      ///< each edge's triangles
  std::vector<int32_t> vertex_begin_, vertex_triangles_;  ///< each vertex's triangles
  bool loose_ = false;  ///< a particle in no triangle: no region (its pairs must be searched)

  // Per frame.
  std::vector<Vec3> normal_;  ///< per triangle, by its winding, unnormalised
  std::vector<int32_t> region_, vertex_region_, edge_region_, frontier_, next_;
  std::vector<uint8_t> node_smooth_;
  int32_t regions_ = 0, in_regions_ = 0;
  std::vector<int32_t> cells_;  ///< the coarse grid: −1 empty, a region, or −2 mixed
  std::vector<uint8_t> triangle_kept_, vertex_kept_, edge_kept_;
};

}  // namespace drape
