// Smooth patches (collision/smooth_patches.h), the parts of a cloth self-collision's search may
// leave out: a region never holds two triangles that cross (checked by the tests' own
// brute-force crossing test, on a ribbon whose normals all pass the cone test), and every pair
// of elements near each other that is not inside one region stays in the search (checked
// against every pair, on a sheet with a flap folded over it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "brute_force_crossings.h"
#include "collision/closest_points.h"
#include "collision/smooth_patches.h"
#include "drape/cloth.h"
#include "drape/scene.h"

namespace drape {
namespace {

// A sheet of n × m quads over the parameter square [0, 1]², placed by `at`, each quad split along
// one diagonal, wound so that a flat sheet faces +z.
template <class At>
std::shared_ptr<ClothMesh> sheet(int n, int m, At&& at) {
  auto mesh = std::make_shared<ClothMesh>();
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) mesh->positions.push_back(at(double(i) / n, double(j) / m));
  auto index = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      mesh->triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh->triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  return mesh;
}

ClothModel model_of(std::shared_ptr<ClothMesh> mesh) {
  ClothDef def;
  def.mesh = std::move(mesh);
  def.mesh_file = "test sheet";
  def.pins.clear();
  def.perturbation = 0.0;
  return build_model(def);
}

// The search's boxes for the triangles at x: their corners' box widened by `margin`.
std::vector<Box> triangle_boxes(const ClothModel& model, const std::vector<Vec3>& x,
                                double margin) {
  std::vector<Box> boxes;
  for (const Triangle& t : model.triangles) {
    Box b{x[t[0]], x[t[0]]};
    for (int32_t p : t) b.lo = b.lo.cwiseMin(x[p]), b.hi = b.hi.cwiseMax(x[p]);
    b.lo.array() -= margin;
    b.hi.array() += margin;
    boxes.push_back(b);
  }
  return boxes;
}

TEST(SmoothPatches, AFlatClothIsOneRegionAndLeavesTheSearchNothing) {
  const ClothModel model =
      model_of(sheet(24, 24, [](double u, double v) { return Vec3(u, v, 0.0); }));
  SmoothPatches patches;
  patches.prepare(model, triangle_edges(model.triangles));
  EXPECT_GT(patches.patches(), 9);  // an octree of several levels
  patches.update(model.triangles, model.rest_position);
  EXPECT_EQ(patches.regions(), 1);
  EXPECT_EQ(patches.triangles_in_regions(), static_cast<int32_t>(model.triangles.size()));
  // The one region is the whole cloth: its every vertex and edge lie in it.
  EXPECT_TRUE(patches.whole());
  const int32_t region = patches.region_of_triangle(0);
  ASSERT_GE(region, 0);
  for (int32_t p = 0; p < model.size(); ++p) EXPECT_EQ(patches.region_of_vertex(p), region);
  const int32_t edges = static_cast<int32_t>(triangle_edges(model.triangles).size());
  for (int32_t e = 0; e < edges; ++e) EXPECT_EQ(patches.region_of_edge(e), region);
  patches.keep(triangle_boxes(model, model.rest_position, 0.02),
               std::vector<uint8_t>(model.triangles.size(), 1));
  for (int32_t t = 0; t < static_cast<int32_t>(model.triangles.size()); ++t)
    EXPECT_FALSE(patches.triangle_kept(t));
  for (int32_t p = 0; p < model.size(); ++p) EXPECT_FALSE(patches.vertex_kept(p));
}

TEST(SmoothPatches, ARegionsNormalsLieWithinItsCone) {
  // A sheet bent round half a cylinder: embedded, its boundary's projection simple, but its
  // normals turn by 180°, so its crease-like sides are not left out of the search.
  const ClothModel model = model_of(sheet(48, 16, [](double u, double v) {
    const double a = std::numbers::pi * u;
    return Vec3(0.3 * std::cos(a), v, 0.3 * std::sin(a));
  }));
  const std::vector<Vec3>& x = model.rest_position;
  SmoothPatches patches;
  patches.prepare(model, triangle_edges(model.triangles));
  patches.update(model.triangles, x);
  EXPECT_GT(patches.regions(), 1);
  EXPECT_FALSE(patches.whole());
  std::vector<Vec3> sum(patches.patches(), Vec3::Zero()), normal;
  for (const Triangle& t : model.triangles)
    normal.push_back((x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]));
  for (int32_t t = 0; t < static_cast<int32_t>(normal.size()); ++t)
    if (patches.region_of_triangle(t) >= 0) sum[patches.region_of_triangle(t)] += normal[t];
  const double cone = SmoothPatches::kConeAngle * std::numbers::pi / 180.0;
  for (int32_t t = 0; t < static_cast<int32_t>(normal.size()); ++t) {
    const int32_t r = patches.region_of_triangle(t);
    if (r < 0) continue;
    EXPECT_GE(normal[t].normalized().dot(sum[r].normalized()), std::cos(cone) - 1e-12) << t;
  }
}

TEST(SmoothPatches, ARibbonWoundThroughItselfIsInNoRegionWhereItCrosses) {
  // An annular ribbon wound 1.2 turns about z, rising and falling gently, so that its last
  // fifth passes through its first: every normal within a few degrees of +z (the cone alone
  // would take the whole ribbon), only its boundary's projection tells.
  const double turns = 1.2, angle = 2.0 * std::numbers::pi * turns;
  const ClothModel model = model_of(sheet(119, 4, [&](double u, double v) {
    const double a = angle * u, r = 1.5 - 0.5 * v;
    return Vec3(r * std::cos(a), r * std::sin(a), 0.05 * std::sin(std::numbers::pi * u));
  }));
  const std::vector<Vec3>& x = model.rest_position;
  SmoothPatches patches;
  patches.prepare(model, triangle_edges(model.triangles));
  patches.update(model.triangles, x);
  for (const Triangle& t : model.triangles) {
    const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).normalized();
    ASSERT_GT(n.z(), std::cos(10.0 * std::numbers::pi / 180.0));
  }
  int64_t crossing = 0;
  const std::vector<Triangle>& tri = model.triangles;
  const int32_t count = static_cast<int32_t>(tri.size());
  for (int32_t s = 0; s < count; ++s)
    for (int32_t t = s + 1; t < count; ++t) {
      if (testing_support::share_a_vertex(tri[s], tri[t]) ||
          !testing_support::triangles_cross(tri[s], tri[t], x))
        continue;
      ++crossing;
      EXPECT_FALSE(SmoothPatches::within_smooth(patches.region_of_triangle(s),
                                                patches.region_of_triangle(t)))
          << "triangles " << s << " and " << t << " cross in region "
          << patches.region_of_triangle(s);
    }
  EXPECT_GT(crossing, 0);  // the ribbon does pass through itself
  EXPECT_FALSE(patches.whole());
  // Its parts that do not overlap are still regions.
  EXPECT_GT(patches.triangles_in_regions(), static_cast<int32_t>(tri.size() / 2));
}

TEST(SmoothPatches, EveryPairNearEachOtherOutsideOneRegionStaysInTheSearch) {
  // A sheet 1 m square of 32 × 32 quads whose last eighth is folded back over it, round a fold
  // of radius 1.5 cm, so that the flap lies 3 cm above the sheet (within the reach below).
  constexpr double kRadius = 0.015, kFold = 0.875;
  const ClothModel model = model_of(sheet(32, 32, [&](double u, double v) {
    if (u <= kFold) return Vec3(u, v, 0.0);
    const double along = u - kFold, half = std::numbers::pi * kRadius;
    if (along <= half) {
      const double a = along / kRadius;
      return Vec3(kFold + kRadius * std::sin(a), v, kRadius * (1.0 - std::cos(a)));
    }
    return Vec3(kFold - (along - half), v, 2.0 * kRadius);
  }));
  const std::vector<Vec3>& x = model.rest_position;
  const double reach = 0.04;
  SmoothPatches patches;
  const std::vector<std::array<int32_t, 2>> edges = triangle_edges(model.triangles);
  patches.prepare(model, edges);
  patches.update(model.triangles, x);
  patches.keep(triangle_boxes(model, x, reach), std::vector<uint8_t>(model.triangles.size(), 1));
  const std::vector<Triangle>& tri = model.triangles;
  int64_t near = 0, searched = 0;
  for (int32_t p = 0; p < model.size(); ++p)
    for (int32_t t = 0; t < static_cast<int32_t>(tri.size()); ++t) {
      if (tri[t][0] == p || tri[t][1] == p || tri[t][2] == p) continue;
      const TrianglePoint q = closest_on_triangle(x[p], x[tri[t][0]], x[tri[t][1]], x[tri[t][2]]);
      const Vec3 d = x[p] - (q.wa * x[tri[t][0]] + q.wb * x[tri[t][1]] + q.wc * x[tri[t][2]]);
      if (d.norm() >= reach) continue;
      ++near;
      if (SmoothPatches::within_smooth(patches.region_of_vertex(p), patches.region_of_triangle(t)))
        continue;
      ++searched;
      EXPECT_TRUE(patches.vertex_kept(p) && patches.triangle_kept(t))
          << "vertex " << p << " and triangle " << t << " are " << d.norm() << " m apart";
    }
  const int32_t edge_count = static_cast<int32_t>(edges.size());
  for (int32_t e = 0; e < edge_count; ++e)
    for (int32_t f = e + 1; f < edge_count; ++f) {
      const auto [i, j] = edges[e];
      const auto [k, l] = edges[f];
      if (i == k || i == l || j == k || j == l) continue;
      const SegmentPoints sp = closest_between_segments(x[i], x[j], x[k], x[l]);
      const Vec3 d = (1 - sp.s) * x[i] + sp.s * x[j] - (1 - sp.t) * x[k] - sp.t * x[l];
      if (d.norm() >= reach ||
          SmoothPatches::within_smooth(patches.region_of_edge(e), patches.region_of_edge(f)))
        continue;
      EXPECT_TRUE(patches.edge_kept(e) && patches.edge_kept(f))
          << "edges " << e << " and " << f << " are " << d.norm() << " m apart";
    }
  // The flap over the sheet is searched; the sheet far from it is not.
  EXPECT_GT(searched, 1000);
  EXPECT_LT(searched, near);
  int32_t left_out = 0;
  for (int32_t t = 0; t < static_cast<int32_t>(tri.size()); ++t)
    left_out += !patches.triangle_kept(t);
  EXPECT_GT(left_out, static_cast<int32_t>(tri.size() / 3));
}

// The flat 16 × 16 sheet with triangle `turned` wound against its neighbours.
ClothModel sheet_turning(int turned) {
  auto mesh = sheet(16, 16, [](double u, double v) { return Vec3(u, v, 0.0); });
  if (turned >= 0) std::swap(mesh->triangles[turned][1], mesh->triangles[turned][2]);
  return model_of(mesh);
}

TEST(SmoothPatches, OnlyDisksWoundOneWayMayBeSmooth) {
  // Triangle 100 lies inside a lowest-level patch: only the winding of its sides tells that
  // the patches holding it, on every level, are not disks wound one way.
  const ClothModel good = sheet_turning(-1), turned = sheet_turning(100);
  SmoothPatches a, b;
  a.prepare(good, triangle_edges(good.triangles));
  b.prepare(turned, triangle_edges(turned.triangles));
  EXPECT_EQ(a.disks(), a.patches());
  EXPECT_EQ(b.patches(), a.patches());
  EXPECT_LT(b.disks(), b.patches());
  b.update(turned.triangles, turned.rest_position);
  EXPECT_EQ(b.region_of_triangle(100), -1);
  EXPECT_GT(b.triangles_in_regions(), 0);
}

TEST(SmoothPatches, AnElementIsInARegionOnlyWhereAllItsTrianglesAre) {
  // Triangle 75 turned, at a lowest-level patch's border: its corner (6, 3) is also a corner of
  // triangle 74, of the next patch, which is smooth. Its corners and sides are in no region,
  // though some of their other triangles are in one.
  const ClothModel turned = sheet_turning(75);
  SmoothPatches b;
  b.prepare(turned, triangle_edges(turned.triangles));
  b.update(turned.triangles, turned.rest_position);
  ASSERT_EQ(b.region_of_triangle(75), -1);
  ASSERT_GE(b.region_of_triangle(74), 0);
  const std::vector<std::array<int32_t, 2>> edges = triangle_edges(turned.triangles);
  const Triangle& t = turned.triangles[75];
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(b.region_of_vertex(t[k]), -1);
    const std::array<int32_t, 2> side{std::min(t[k], t[(k + 1) % 3]),
                                      std::max(t[k], t[(k + 1) % 3])};
    const auto e = std::lower_bound(edges.begin(), edges.end(), side) - edges.begin();
    EXPECT_EQ(b.region_of_edge(static_cast<int32_t>(e)), -1);
  }
}

}  // namespace
}  // namespace drape
