// Stepping allocates nothing (the design's rule; set-up may): this program counts the C
// library's allocation calls (it defines malloc, calloc, realloc and aligned_alloc, forwarding
// to glibc's own, so every allocation in the process passes here, operator new's included) and
// checks that a run's later frames, where the factorisations are made again, make none.
// Without glibc's entry points, or under AddressSanitizer (which replaces malloc itself), the
// tests are skipped.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <string>

#include "drape/material.h"
#include "drape/simulation.h"
#include "solvers/sparse_cholesky.h"
#include "test_scenes.h"

// AddressSanitizer: GCC says so with __SANITIZE_ADDRESS__, Clang with __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define DRAPE_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DRAPE_UNDER_ASAN 1
#endif
#endif

#if defined(__GLIBC__) && !defined(DRAPE_UNDER_ASAN)
#define DRAPE_COUNTS_ALLOCATIONS 1
namespace {
std::atomic<long> allocations{0};
}
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void* malloc(size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(size_t count, size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void* realloc(void* p, size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
}
#endif

namespace drape {
namespace {

// Allocations made by f().
template <class F>
long allocations_in(F f) {
#ifdef DRAPE_COUNTS_ALLOCATIONS
  const long before = allocations.load();
  f();
  return allocations.load() - before;
#else
  f();
  return 0;
#endif
}

#ifdef DRAPE_COUNTS_ALLOCATIONS
constexpr bool kCounting = true;
#else
constexpr bool kCounting = false;
#endif

TEST(Allocations, TheCounterSeesThem) {
  if (!kCounting) GTEST_SKIP() << "allocations are not counted in this build";
  void* (*volatile allocate)(size_t) = std::malloc;  // not elided
  void* p = nullptr;
  EXPECT_EQ(allocations_in([&] { p = allocate(100); }), 1);
  std::free(p);
}

TEST(Allocations, ASparseFactorisationAndItsSolvesAllocateNothing) {
  // A 2D Laplacian plus mass, 4096 unknowns (under the 16 384 rows whose work Eigen keeps on
  // the stack), factorised again with new values.
  const int side = 64, n = side * side;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 5.0);
    if (i % side + 1 < side) t.emplace_back(i + 1, i, -1.0), t.emplace_back(i, i + 1, -1.0);
    if (i + side < n) t.emplace_back(i + side, i, -1.0), t.emplace_back(i, i + side, -1.0);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  SparseCholesky cholesky;
  cholesky.analyse(a);
  ASSERT_TRUE(cholesky.factorise());
  Eigen::VectorXd x = Eigen::VectorXd::Ones(n);
  SparseCholesky::Rows3 three = SparseCholesky::Rows3::Ones(n, 3);
  const long during = allocations_in([&] {
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < n; ++i) cholesky.values()[cholesky.find(i, i)] = 5.0 + k;
      ASSERT_TRUE(cholesky.factorise());
      cholesky.solve_in_place(x);
      cholesky.solve3_in_place(three);
    }
  });
  if (kCounting) {
    EXPECT_EQ(during, 0);
  }
  // And it solves: A·x = b back through the permutation, with the last values (diagonal 7).
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0), pb(n);
  for (int i = 0; i < n; ++i) pb[cholesky.permutation()[i]] = b[i];
  cholesky.solve_in_place(pb);
  Eigen::VectorXd solution(n);
  for (int i = 0; i < n; ++i) solution[i] = pb[cholesky.permutation()[i]];
  Eigen::SparseMatrix<double> last = a;
  for (int i = 0; i < n; ++i) last.coeffRef(i, i) = 7.0;
  const Eigen::VectorXd product = last * solution;
  for (int i = 0; i < n; ++i) EXPECT_NEAR(product[i], b[i], 1e-12) << i;
  // Three right-hand sides at once: as three solves, to round-off.
  SparseCholesky::Rows3 rhs(n, 3);
  for (int i = 0; i < n; ++i) rhs.row(i) << std::sin(0.1 * i), std::cos(0.3 * i), 1.0 + (i % 7);
  SparseCholesky::Rows3 together = rhs;
  cholesky.solve3_in_place(together);
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd alone = rhs.col(c);
    cholesky.solve_in_place(alone);
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(together(i, c), alone[i], 1e-14 * (1.0 + std::abs(alone[i]))) << i << " " << c;
  }
  // And the first loop's three solves matched the single ones with the same factors.
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(three(i, c), x[i], 1e-14) << i;
}

// Frames after the first ones (where the solvers size what they find: contacts, factors)
// allocate nothing.
void expect_quiet_frames(SceneDef def, int warm_up, int counted) {
  if (!kCounting) GTEST_SKIP() << "allocations are not counted in this build";
  Simulation sim(def);
  for (int f = 0; f < warm_up; ++f) ASSERT_TRUE(sim.step()) << sim.divergence();
  bool stepped = true;
  const long during = allocations_in([&] {
    for (int f = 0; f < counted; ++f) stepped = stepped && sim.step();
  });
  ASSERT_TRUE(stepped) << sim.divergence();
  EXPECT_EQ(during, 0) << counted << " frames after " << warm_up;
}

TEST(Allocations, FastOnTheSphereRefactorisesAsContactsChangeAndAllocatesNothing) {
  // The seed's cloth landing on the sphere: the set of particles held at the sphere changes
  // frame by frame, and `fast` factorises its matrix again each time.
  SceneDef def = testing_support::shipped("sphere");
  def.solver.method = Method::fast;
  expect_quiet_frames(def, 60, 60);
}

TEST(Allocations, ImplicitWithItsFactorOnAFineStiffStripAllocatesNothing) {
  // The lab's kind of strip, clamped at one end and sagging: block-Jacobi CG is slow, so
  // `implicit` makes a factor (its first, in the warm-up) and factorises it again as the strip
  // moves.
  SceneDef def;
  def.cloth.material = material_preset("denim");
  def.cloth.cols = 82;
  def.cloth.rows = 4;
  def.cloth.width = 0.2;
  def.cloth.height = 0.0075;
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.perturbation = 0.0;
  def.cloth.pins.clear();
  for (int r = 0; r < 4; ++r) def.cloth.pins.push_back({0, r}), def.cloth.pins.push_back({1, r});
  def.solver.method = Method::implicit;
  expect_quiet_frames(def, 30, 60);
}

}  // namespace
}  // namespace drape
