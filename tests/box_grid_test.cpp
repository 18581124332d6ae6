// The broad phase against brute force: every overlapping pair of boxes, and no other, is
// reported exactly once, whatever the boxes' sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/box_grid.h"
#include "collision/dense_grid.h"

namespace drape {
namespace {

bool overlap(const Box& a, const Box& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

// `count` boxes in a 1 m cube: most small, a few long thin ones across many cells, a few huge;
// some share a face exactly (touching counts as overlapping).
std::vector<Box> random_boxes(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> at(0.0, 1.0), size(0.005, 0.05);
  std::vector<Box> boxes;
  for (int i = 0; i < count; ++i) {
    const Vec3 lo(at(rng), at(rng), at(rng));
    Vec3 extent(size(rng), size(rng), size(rng));
    if (i % 17 == 0) extent[i % 3] = 0.6;           // long and thin
    if (i % 97 == 0) extent = Vec3::Constant(0.4);  // huge
    boxes.push_back({lo, lo + extent});
    if (i % 13 == 0) {  // one touching the last box's face exactly
      Box touching = boxes.back();
      touching.lo.x() = touching.hi.x();
      touching.hi.x() += 0.01;
      boxes.push_back(touching);
      ++i;
    }
  }
  return boxes;
}

std::set<std::pair<int32_t, int32_t>> brute_force(const std::vector<Box>& boxes,
                                                  const std::vector<int32_t>& kept, int32_t split) {
  std::set<std::pair<int32_t, int32_t>> pairs;
  for (const int32_t s : kept)
    for (const int32_t t : kept)
      if (s < t && overlap(boxes[s], boxes[t]) && (split < 0 || (s < split && t >= split)))
        pairs.insert({s, t});
  return pairs;
}

TEST(BoxGrid, ReportsEveryOverlappingPairOnceAndNoOther) {
  for (const unsigned seed : {1u, 2u, 3u}) {
    const std::vector<Box> boxes = random_boxes(600, seed);
    std::vector<int32_t> kept;
    for (int32_t i = 0; i < static_cast<int32_t>(boxes.size()); ++i)
      if (i % 11 != 5) kept.push_back(i);  // boxes left out are never reported
    BoxGrid grid;
    grid.build(boxes, kept);
    ASSERT_GT(grid.cells(), 8) << "the test needs a grid of many cells";
    std::vector<std::pair<int32_t, int32_t>> found;
    for (int64_t c = 0; c < grid.cells(); ++c)
      grid.each_pair_in(c, [&](int32_t s, int32_t t) {
        EXPECT_LT(s, t);
        found.push_back({s, t});
      });
    const std::set<std::pair<int32_t, int32_t>> once(found.begin(), found.end());
    EXPECT_EQ(once.size(), found.size()) << "a pair reported twice, seed " << seed;
    const auto expected = brute_force(boxes, kept, -1);
    EXPECT_GT(expected.size(), 150u);
    EXPECT_EQ(once, expected) << "seed " << seed;
  }
}

TEST(BoxGrid, ReportsEveryPairAcrossASplitOnce) {
  const std::vector<Box> boxes = random_boxes(500, 7);
  std::vector<int32_t> kept(boxes.size());
  for (int32_t i = 0; i < static_cast<int32_t>(boxes.size()); ++i) kept[i] = i;
  const int32_t split = 200;
  BoxGrid grid;
  grid.build(boxes, kept);
  std::vector<std::pair<int32_t, int32_t>> found;
  for (int64_t c = 0; c < grid.cells(); ++c)
    grid.each_pair_across(c, split, [&](int32_t s, int32_t t) { found.push_back({s, t}); });
  const std::set<std::pair<int32_t, int32_t>> once(found.begin(), found.end());
  EXPECT_EQ(once.size(), found.size());
  const auto expected = brute_force(boxes, kept, split);
  EXPECT_GT(expected.size(), 40u);
  EXPECT_EQ(once, expected);
}

// A grid's cell or size as an array gtest can compare and print.
std::array<int, 3> ints(const Eigen::Array3i& a) {
  return {a.x(), a.y(), a.z()};
}

// The dense coarse grids' size and cells (collision/dense_grid.h): exact where small, widened
// to at most the cells allowed where the span is vast (pieces 1e10 m apart once overflowed an
// int), one cell where the span overflows a double, and every point, even one outside or not a
// number, in a cell of the grid.
TEST(DenseGrid, IsExactWhereSmallBoundedWhereVastAndHoldsEveryPoint) {
  double cell = 0.1;
  Eigen::Array3i dims = dense_grid_dims(Vec3(1.0, 0.55, 0.25), cell, 1000);
  EXPECT_EQ(cell, 0.1);
  EXPECT_EQ(ints(dims), (std::array<int, 3>{11, 6, 3}));
  dims = dense_grid_dims(Vec3(1.0, 0.55, 0.25), cell, 100);  // 198 cells: one doubling
  EXPECT_EQ(cell, 0.2);
  EXPECT_EQ(ints(dims), (std::array<int, 3>{6, 3, 2}));

  const int64_t most = int64_t{1} << 21;
  cell = 0.04;
  dims = dense_grid_dims(Vec3(1e10, 1e10, 0.1), cell, most);
  EXPECT_GE(dims.minCoeff(), 1);
  EXPECT_LE(dims.cast<int64_t>().prod(), most);
  const double narrower = std::floor(1e10 / (0.5 * cell)) + 1.0;  // widened only as needed
  EXPECT_GT(narrower * narrower, static_cast<double>(most));
  EXPECT_EQ(ints(dense_grid_cell(Vec3(1e10, 0.0, 0.0), Vec3::Zero(), cell, dims)),
            (std::array<int, 3>{dims.x() - 1, 0, 0}));

  const double huge = std::numeric_limits<double>::max();
  cell = 0.04;
  dims = dense_grid_dims(Vec3(huge, 1.0, 1.0) - Vec3(-huge, 0.0, 0.0), cell, most);
  EXPECT_EQ(ints(dims), (std::array<int, 3>{1, 1, 1}));
  EXPECT_TRUE(std::isinf(cell));
  const Vec3 origin(-huge, 0.0, 0.0);
  for (const Vec3& p : {Vec3(huge, 0.5, 0.5), Vec3(0.0, 0.0, 0.0), Vec3(-huge, 1.0, 1.0)})
    EXPECT_EQ(ints(dense_grid_cell(p, origin, cell, dims)), (std::array<int, 3>{0, 0, 0}));

  dims = Eigen::Array3i(4, 5, 6);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ints(dense_grid_cell(Vec3(-3.0, 99.0, nan), Vec3::Zero(), 1.0, dims)),
            (std::array<int, 3>{0, 4, 0}));
  EXPECT_EQ(ints(dense_grid_cell(Vec3(2.5, 0.0, 5.0), Vec3::Zero(), 1.0, dims)),
            (std::array<int, 3>{2, 0, 5}));
}

}  // namespace
}  // namespace drape
