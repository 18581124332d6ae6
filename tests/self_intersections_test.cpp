// The self-intersection count against a brute-force count written for the tests on its own
// (brute_force_crossings.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "brute_force_crossings.h"
#include "collision/crossings.h"
#include "drape/self_intersections.h"
#include "drape/simulation.h"
#include "io/run_stats.h"

namespace {

using drape::Triangle;
using drape::Vec3;

struct Mesh {
  std::vector<Vec3> x;
  std::vector<Triangle> triangles;
};

// Appends a grid of (cols + 1) × (rows + 1) vertices at corner(i, j), two triangles per quad
// split along the diagonal from (i, j) to (i + 1, j + 1).
template <class Corner>
void add_grid(Mesh& m, int cols, int rows, Corner corner) {
  const int32_t first = static_cast<int32_t>(m.x.size());
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= cols; ++i) m.x.push_back(corner(i, j));
  auto at = [&](int i, int j) { return first + j * (cols + 1) + i; };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

int64_t brute_force_count(const Mesh& m) {
  return drape::testing_support::brute_force_crossings(m.triangles, m.x);
}

int64_t library_count(const Mesh& m) {
  return drape::count_self_intersections(m.triangles, m.x);
}

// A unit square cloth of n × n quads, each vertex displaced by up to `amplitude` quad widths
// along each axis at random.
Mesh crumpled(int n, double amplitude, unsigned seed) {
  Mesh m;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> offset(-amplitude / n, amplitude / n);
  add_grid(m, n, n, [&](int i, int j) {
    return Vec3(static_cast<double>(i) / n + offset(random),
                static_cast<double>(j) / n + offset(random), offset(random));
  });
  return m;
}

TEST(SelfIntersections, FlatClothHasNone) {
  Mesh m;
  add_grid(m, 40, 30, [](int i, int j) { return Vec3(0.1 * i, 0.05 * j, 0.0); });
  EXPECT_EQ(library_count(m), 0);
  EXPECT_EQ(brute_force_count(m), 0);
}

TEST(SelfIntersections, ASimulationStartsWithNone) {
  const drape::Simulation sim(drape::SceneDef{});
  EXPECT_EQ(drape::count_self_intersections(sim.model().triangles, sim.state().x), 0);
}

// Grid A in the plane z = 0 (quads of 1 m), grid B in the plane x = c: they meet along the line
// x = c, z = 0, where the triangles of A's column of quads around x = c and of B's row around
// z = 0 each cover an interval of y. A pair crosses exactly when its intervals overlap.
TEST(SelfIntersections, TwoCrossingGridsCrossAlongTheirLine) {
  const int a_size = 8, b_cols = 4, b_rows = 5;
  const double c = 3.3, y0 = 1.45, z0 = -2.6;
  Mesh m;
  add_grid(m, a_size, a_size, [](int i, int j) { return Vec3(i, j, 0.0); });
  add_grid(m, b_cols, b_rows, [&](int i, int j) { return Vec3(c, y0 + i, z0 + j); });
  // A's quad column 3: the diagonal meets x = c at y = j + f; the lower triangle covers
  // [j, j + f], the upper [j + f, j + 1]. B's quad row 2: its diagonal meets z = 0 at
  // y = y0 + i + g; its first triangle covers [y0 + i + g, y0 + i + 1], its second the rest.
  const double f = c - 3.0, g = 0.0 - (z0 + 2.0);
  struct Interval {
    double lo, hi;
  };
  std::vector<Interval> a, b;
  for (int j = 0; j < a_size; ++j) a.push_back({j + 0.0, j + f}), a.push_back({j + f, j + 1.0});
  for (int i = 0; i < b_cols; ++i)
    b.push_back({y0 + i + g, y0 + i + 1.0}), b.push_back({y0 + i, y0 + i + g});
  int64_t expected = 0;
  for (const Interval& s : a)
    for (const Interval& t : b) expected += std::min(s.hi, t.hi) - std::max(s.lo, t.lo) > 1e-9;
  // Over B's 4 m of the line, A's 8 interval ends and B's 7 inner ones cut it into 16 pieces,
  // each the overlap of one pair.
  EXPECT_EQ(expected, 16);
  EXPECT_EQ(brute_force_count(m), expected);
  EXPECT_EQ(library_count(m), expected);
}

TEST(SelfIntersections, CrumpledClothMatchesBruteForce) {
  for (const double amplitude : {0.3, 0.8, 1.5, 3.0}) {
    for (const unsigned seed : {1u, 2u, 3u}) {
      const Mesh m = crumpled(24, amplitude, seed);
      const int64_t expected = brute_force_count(m);
      EXPECT_EQ(library_count(m), expected) << "amplitude " << amplitude << ", seed " << seed;
      if (amplitude >= 1.5) {
        EXPECT_GT(expected, 0) << "the test should crumple the cloth";
      }
    }
  }
}

// A folded cloth: the same sheet twice, the second shifted through the first.
TEST(SelfIntersections, CrumpledAndFoldedMatchBruteForceOnAMeshOfManyCells) {
  Mesh m = crumpled(20, 1.0, 7);
  const Mesh other = crumpled(20, 1.0, 8);
  const int32_t first = static_cast<int32_t>(m.x.size());
  for (const Vec3& x : other.x) m.x.push_back(Vec3(x.x() + 0.013, x.z(), x.y() - 0.5));
  for (const Triangle& t : other.triangles)
    m.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
  const int64_t expected = brute_force_count(m);
  EXPECT_GT(expected, 20);
  EXPECT_EQ(library_count(m), expected);
}

TEST(SelfIntersections, PairsSharingAVertexAreNeverCounted) {
  // B's edge from (0.3, 0.3, -1) to (0.3, 0.3, 1) passes through A's inside.
  Mesh m;
  m.x = {Vec3(0, 0, 0),      Vec3(1, 0, 0),     Vec3(0, 1, 0),
         Vec3(0.3, 0.3, -1), Vec3(0.3, 0.3, 1), Vec3(0, 0, 0)};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};  // sharing vertex 0
  EXPECT_EQ(library_count(m), 0);
  m.triangles = {{0, 1, 2}, {5, 3, 4}};  // the same place, another vertex
  EXPECT_EQ(library_count(m), 1);
  EXPECT_EQ(brute_force_count(m), 1);
}

TEST(SelfIntersections, TouchingIsNotCrossing) {
  Mesh m;
  // A corner of B on A's inside, B standing on A; then an edge of B lying in A's plane across
  // it; then B in A's plane, overlapping it.
  m.x = {Vec3(0, 0, 0),     Vec3(1, 0, 0),     Vec3(0, 1, 0),
         Vec3(0.2, 0.2, 0), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(library_count(m), 0);
  m.x[4] = Vec3(0.6, -0.5, 0);
  EXPECT_EQ(library_count(m), 0);
  m.x[5] = Vec3(0.5, 0.5, 0);
  EXPECT_EQ(library_count(m), 0);
  m.x[5] = Vec3(0.5, 0.5, 1e-3);  // lifted off the plane: its edge 3-4 still lies in it
  EXPECT_EQ(library_count(m), 0);
  m.x[3] = Vec3(0.2, 0.2, -1e-3);  // now the edge 3-5 passes through
  EXPECT_EQ(library_count(m), 1);
  EXPECT_EQ(brute_force_count(m), 1);
}

// The side a CertifiedPlane gives is never wrong, checked against the determinant computed
// exactly in integers: points with coordinates k·2⁻²⁰ for integers |k| < 2³⁷ (exact in doubles,
// whose products of differences are not), the fourth point a + i·(b − a) + j·(c − a) for small
// integers i and j, on the plane exactly (no side may be told), or that point a unit off it
// (each side told must be right), or anywhere.
TEST(SelfIntersections, CertifiedPlaneSidesAreNeverWrong) {
  __extension__ using Wide = __int128;
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int64_t> coordinate(-(int64_t(1) << 37), int64_t(1) << 37);
  std::uniform_int_distribution<int64_t> small(-3, 3), axis(0, 2);
  const double unit = std::ldexp(1.0, -20);
  auto exact_side = [](const int64_t* a, const int64_t* b, const int64_t* c, const int64_t* d) {
    // orientation's det[a − d, b − d, c − d] in 128-bit integers (differences under 2⁴¹).
    Wide u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) u[k] = a[k] - d[k], v[k] = b[k] - d[k], w[k] = c[k] - d[k];
    const Wide det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0]);
    return det > 0 ? 1 : det < 0 ? -1 : 0;
  };
  int told[3] = {0, 0, 0}, untold[3] = {0, 0, 0};  // on the plane, a unit off, anywhere
  for (int trial = 0; trial < 30000; ++trial) {
    const int kind = trial % 3;
    int64_t p[4][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) p[i][k] = coordinate(rng);
    const int64_t i = small(rng), j = small(rng);
    for (int k = 0; k < 3; ++k)
      p[3][k] =
          kind == 2 ? coordinate(rng) : p[0][k] + i * (p[1][k] - p[0][k]) + j * (p[2][k] - p[0][k]);
    if (kind == 1) p[3][axis(rng)] += small(rng) < 0 ? -1 : 1;
    Vec3 x[4];
    for (int v = 0; v < 4; ++v)
      x[v] = Vec3(double(p[v][0]) * unit, double(p[v][1]) * unit, double(p[v][2]) * unit);
    const int side = drape::CertifiedPlane::of(x[0], x[1], x[2]).side(x[3]);
    const int exact = exact_side(p[0], p[1], p[2], p[3]);
    if (side != 0) {
      ASSERT_EQ(side, exact) << "trial " << trial;
    }
    ++(side != 0 ? told : untold)[kind];
  }
  std::printf("sides told / not told: on the plane %d / %d, a unit off %d / %d, anywhere %d / %d\n",
              told[0], untold[0], told[1], untold[1], told[2], untold[2]);
  EXPECT_EQ(told[0], 0);
  EXPECT_GE(told[1], 9000);  // a unit is 2⁻³⁷ of the coordinates, far above doubles' rounding
  EXPECT_EQ(untold[2], 0);
}

TEST(SelfIntersections, NonFiniteTrianglesAreLeftOut) {
  Mesh m = crumpled(16, 1.5, 4);
  const int64_t before = library_count(m);
  m.x[0] = Vec3(std::nan(""), 0, 0);
  m.x[1] = Vec3(1e300, -1e300, 0);
  const int64_t after = library_count(m);
  EXPECT_GE(after, 0);
  EXPECT_LE(after, before + 16);  // the huge triangles may cross some; nothing hangs or throws
}

// Self-collision's fail-safe asks only for the pairs with a suspect triangle (one it moved or
// that lies at a contact): the finder must return exactly the crossing pairs, each against the
// brute-force test, of which one triangle or both are suspects, whatever the suspects (none,
// a few scattered, a block, all of them).
TEST(SelfIntersections, SuspectsGetEveryCrossingPairTheyAreIn) {
  Mesh m = crumpled(24, 1.5, 5);
  m.x[3] = Vec3(std::nan(""), 0, 0);  // triangles with a non-finite corner are left out
  const int32_t count = static_cast<int32_t>(m.triangles.size());
  std::vector<drape::TrianglePair> all;
  drape::CrossingFinder finder;
  finder.find(m.triangles, m.x, all);
  ASSERT_GT(all.size(), 50u) << "the test should crumple the cloth";
  for (const drape::TrianglePair& p : all)
    ASSERT_TRUE(drape::testing_support::triangles_cross(m.triangles[p.s], m.triangles[p.t], m.x));
  std::mt19937 random(3);
  for (const double share : {0.0, 0.02, 0.3, 1.0}) {
    std::vector<uint8_t> suspect(count);
    std::bernoulli_distribution pick(share);
    for (uint8_t& s : suspect) s = pick(random);
    if (share == 0.3)  // and a block, so that whole cells hold none
      std::fill(suspect.begin(), suspect.begin() + count / 2, 0);
    std::vector<drape::TrianglePair> expected, found;
    for (const drape::TrianglePair& p : all)
      if (suspect[p.s] || suspect[p.t]) expected.push_back(p);
    finder.find(m.triangles, m.x, &suspect, found);
    ASSERT_EQ(found.size(), expected.size()) << "share " << share;
    for (size_t k = 0; k < found.size(); ++k) {
      EXPECT_EQ(found[k].s, expected[k].s) << "share " << share;
      EXPECT_EQ(found[k].t, expected[k].t) << "share " << share;
    }
    if (share > 0.0) {
      EXPECT_FALSE(found.empty()) << "share " << share;
    }
  }
}

TEST(SelfIntersections, SameCountOnOneAndTwoThreads) {
#ifdef _OPENMP
  const Mesh m = crumpled(96, 1.5, 11);
  const int previous = omp_get_max_threads();
  omp_set_num_threads(1);
  const int64_t one = library_count(m);
  omp_set_num_threads(2);
  const int64_t two = library_count(m);
  omp_set_num_threads(previous);
  EXPECT_GT(one, 0);
  EXPECT_EQ(one, two);
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
}

TEST(SelfIntersections, LargeCrumpledClothIsCounted) {
  // 256 × 256 quads, 131,072 triangles: the broad phase keeps this far from the 8.6e9 pairs.
  const Mesh m = crumpled(256, 1.5, 5);
  std::printf("256x256 crumpled: %lld self-intersections\n",
              static_cast<long long>(library_count(m)));
}

TEST(SelfIntersections, StatsCarryTheCount) {
  const drape::Simulation sim(drape::SceneDef{});
  const nlohmann::json stats = drape::io::stats_json(sim, drape::io::RunResult{});
  ASSERT_TRUE(stats.contains("self_intersections"));
  EXPECT_TRUE(stats["self_intersections"].is_number_integer());
  EXPECT_EQ(stats["self_intersections"], 0);
}

}  // namespace
