// Micro-benchmarks of the per-substep kernels on an N×N hanging cloth:
//   build/bench/drape_kernels --benchmark_filter=Springs
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "collision/box_grid.h"
#include "drape/collider.h"
#include "drape/self_intersections.h"
#include "drape/simulation.h"
#include "forces.h"
#include "solvers/xpbd/constraints.h"

namespace drape {
namespace {

SceneDef grid(int n) {
  SceneDef def;
  def.cloth.cols = def.cloth.rows = n;
  def.solver.substeps = 1;
  return def;
}

void Springs(benchmark::State& st) {
  const Simulation sim(grid(static_cast<int>(st.range(0))));
  std::vector<Vec3> f(sim.model().size(), Vec3::Zero());
  for (auto _ : st) {
    forces::add_springs(sim.model(), sim.state().x, sim.state().v, f);
    benchmark::DoNotOptimize(f.data());
  }
  st.SetItemsProcessed(st.iterations() * sim.model().springs.size());
}
BENCHMARK(Springs)->Arg(32)->Arg(128)->Arg(256);

// One colour of XPBD distance projections as the xpbd sweep runs them: the vertical springs of
// every other row of an N×N grid in structure-of-arrays storage (base positions and moves), in
// double or float.
template <typename Real>
void Projection(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const Real spacing = Real(2) / static_cast<Real>(n - 1);
  std::vector<Real> bx(n * n), by(n * n), bz(n * n, Real(0)), w(n * n, Real(n) * Real(n));
  for (int i = 0; i < n * n; ++i) {
    bx[i] = static_cast<Real>(i % n) * spacing;
    by[i] = -static_cast<Real>(i / n) * spacing * Real(1.001);  // stretched 0.1%
  }
  std::vector<Real> mx(n * n, Real(0)), my(n * n, Real(0)), mz(n * n, Real(0));
  const Real alpha_tilde = Real(1e-5) * Real(3600 * 400), gamma = Real(1e-5) * Real(60 * 20);
  int64_t springs = 0;
  for (auto _ : st) {
    for (int r = 0; r + 1 < n; r += 2) {
      const int i0 = r * n, j0 = i0 + n;
#pragma omp simd
      for (int c = 0; c < n; ++c)
        xpbd_project<false, true>(bx.data(), by.data(), bz.data(), mx.data(), my.data(), mz.data(),
                                  w.data(), i0 + c, j0 + c, spacing, alpha_tilde, gamma, Real(0));
      springs += n;
    }
    benchmark::DoNotOptimize(mx.data());
  }
  st.SetItemsProcessed(springs);
}
BENCHMARK(Projection<double>)->Arg(32)->Arg(128)->Arg(256);
BENCHMARK(Projection<float>)->Arg(32)->Arg(128)->Arg(256);

void Normals(benchmark::State& st) {
  Simulation sim(grid(static_cast<int>(st.range(0))));
  ClothState state = sim.state();
  for (auto _ : st) {
    update_normals(sim.model(), state);
    benchmark::DoNotOptimize(state.normal.data());
  }
  st.SetItemsProcessed(st.iterations() * sim.model().size());
}
BENCHMARK(Normals)->Arg(32)->Arg(128)->Arg(256);

void Contacts(benchmark::State& st) {
  SceneDef def = grid(static_cast<int>(st.range(0)));
  def.colliders.push_back({});
  ColliderDef plane;
  plane.type = ColliderType::plane;
  plane.center = Vec3(0, 1.0, 0);
  plane.normal = Vec3::UnitY();
  plane.friction = 0.3;
  plane.thickness = 0.01;
  def.colliders.push_back(plane);
  Simulation sim(def);
  ClothState state = sim.state();
  for (auto _ : st) {
    resolve_contacts(sim.colliders(), state);
    benchmark::DoNotOptimize(state.x.data());
  }
  st.SetItemsProcessed(st.iterations() * sim.model().size());
}
BENCHMARK(Contacts)->Arg(32)->Arg(128)->Arg(256);

// The xpbd contact pass (PositionContact, branch-free) over an N×N grid in structure-of-arrays
// storage against a sphere, in double or float. Its cost does not depend on how many particles
// touch: every slot is evaluated.
template <typename Real>
void PositionContacts(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const Real spacing = Real(2) / static_cast<Real>(n - 1);
  std::vector<Real> bx(n * n), by(n * n, Real(0.45)), bz(n * n), w(n * n, Real(1));
  for (int i = 0; i < n * n; ++i) {
    bx[i] = static_cast<Real>(i % n) * spacing - Real(1);
    bz[i] = static_cast<Real>(i / n) * spacing - Real(1);
  }
  std::vector<Real> mx(n * n, Real(0)), my(n * n, Real(-0.01)), mz(n * n, Real(0));
  ColliderDef sphere;
  sphere.friction = 0.4;
  const PositionContact<Real> contact(make_collider(sphere));
  for (auto _ : st) {
#pragma omp simd
    for (int i = 0; i < n * n; ++i)
      contact.apply(w[i] > Real(0), bx[i] + mx[i], by[i] + my[i], bz[i] + mz[i], mx[i], my[i],
                    mz[i]);
    benchmark::DoNotOptimize(mx.data());
  }
  st.SetItemsProcessed(st.iterations() * n * n);
}
BENCHMARK(PositionContacts<double>)->Arg(128)->Arg(256);
BENCHMARK(PositionContacts<float>)->Arg(128)->Arg(256);

// The hang-lr cloth (long-range attachments) for xpbd at n = range(0), in single precision when
// range(1), at `substeps` a frame.
SceneDef xpbd_grid(const benchmark::State& st, int substeps) {
  SceneDef def = grid(static_cast<int>(st.range(0)));
  def.solver.method = Method::xpbd;
  def.solver.precision = st.range(1) ? Precision::f32 : Precision::f64;
  def.solver.substeps = substeps;
  def.cloth.long_range.enabled = true;
  return def;
}

// One frame of xpbd at 20 substeps with long-range attachments (hang-lr), in each precision,
// with and without stiff sweeps (each a sweep of the structural springs alone).
void XpbdFrame(benchmark::State& st) {
  SceneDef def = xpbd_grid(st, 20);
  def.solver.stiff_sweeps = static_cast<int>(st.range(2));
  Simulation sim(def);
  for (auto _ : st) sim.step();
  st.SetItemsProcessed(st.iterations() * sim.model().size() * def.solver.substeps);
}
BENCHMARK(XpbdFrame)
    ->ArgsProduct({{128, 256}, {0, 1}, {0, 3}})
    ->ArgNames({"n", "single", "stiff_sweeps"});

// One frame of xpbd at 4 substeps with line passes (each an exact solve of every row and column
// of structural springs, after the attachments), with and without a stiff sweep after them, on
// the same cloth; items are particles × substeps × passes.
void XpbdLinesFrame(benchmark::State& st) {
  SceneDef def = xpbd_grid(st, 4);
  def.solver.line_passes = static_cast<int>(st.range(2));
  def.solver.stiff_sweeps = static_cast<int>(st.range(3));
  Simulation sim(def);
  for (auto _ : st) sim.step();
  st.SetItemsProcessed(st.iterations() * sim.model().size() * def.solver.substeps *
                       def.solver.line_passes);
}
BENCHMARK(XpbdLinesFrame)
    ->ArgsProduct({{64, 128, 256}, {0, 1}, {2, 6}, {0, 1}})
    ->ArgNames({"n", "single", "line_passes", "stiff_sweeps"});

// A closed UV sphere of `radius` at the origin with 2·segments·(rings − 1) triangles.
ClothMesh uv_sphere(double radius, int segments, int rings) {
  ClothMesh m;
  m.positions.push_back(Vec3(0.0, radius, 0.0));
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * M_PI * s / segments;
      m.positions.push_back(radius * Vec3(std::sin(theta) * std::sin(phi), std::cos(theta),
                                          std::sin(theta) * std::cos(phi)));
    }
  }
  m.positions.push_back(Vec3(0.0, -radius, 0.0));
  const int32_t south = static_cast<int32_t>(m.positions.size()) - 1;
  auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, at(1, s), at(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      m.triangles.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      m.triangles.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
    m.triangles.push_back({at(rings - 1, s), south, at(rings - 1, s + 1)});
  }
  return m;
}

// An n×n cloth, level at `height` over a 0.5 m sphere at the origin, for xpbd at 20 substeps.
SceneDef over_sphere(int n, double height) {
  SceneDef def = grid(n);
  def.cloth.orientation = Orientation::horizontal;
  def.cloth.origin = Vec3(-1.0, height, -1.0);
  def.cloth.pins.clear();
  def.solver.method = Method::xpbd;
  def.solver.substeps = 20;
  ColliderDef sphere;
  sphere.radius = 0.5;
  def.colliders = {sphere};
  return def;
}

// One xpbd frame (20 substeps) of a 64×64 cloth lying on a 0.5 m sphere: the analytic sphere
// (range(0) = 0) or a closed mesh of about 100 000 triangles (range(0) = 1), queried through
// its BVH by the generic contact path. The cloth starts at rest on the sphere's top.
void MeshColliderFrame(benchmark::State& st) {
  SceneDef def = over_sphere(64, 0.52);
  ColliderDef& sphere = def.colliders.front();
  if (st.range(0)) {
    sphere.type = ColliderType::mesh;
    sphere.mesh = std::make_shared<const ClothMesh>(uv_sphere(0.5, 256, 197));
    sphere.transform.rotate = Vec3(90.0, 0.0, 0.0);  // no pole under the cloth's middle
  }
  Simulation sim(def);
  for (int f = 0; f < 30; ++f) sim.step();  // draped: most particles touch or nearly
  for (auto _ : st) sim.step();
  st.counters["triangles"] = st.range(0) ? double(sphere.mesh->triangles.size()) : 0.0;
}
BENCHMARK(MeshColliderFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Self-collision's broad phase on an N×N cloth draped over a sphere (30 frames of xpbd): the
// grid over its edges' boxes, widened by half the default reach (half the mean edge), built,
// then every overlapping pair visited, cell by cell on one thread. Counts the pairs.
void EdgeBoxPairs(benchmark::State& st) {
  Simulation sim(over_sphere(static_cast<int>(st.range(0)), 0.7));
  for (int f = 0; f < 30; ++f) sim.step();
  const std::vector<Vec3>& x = sim.state().x;
  const double margin = 0.25 * sim.model().mean_edge;
  std::vector<Box> boxes;
  std::vector<int32_t> kept;
  for (const auto& [i, j] : triangle_edges(sim.model().triangles)) {
    Box b{x[i].cwiseMin(x[j]), x[i].cwiseMax(x[j])};
    b.lo.array() -= margin;
    b.hi.array() += margin;
    kept.push_back(static_cast<int32_t>(boxes.size()));
    boxes.push_back(b);
  }
  BoxGrid boxgrid;
  int64_t pairs = 0;
  for (auto _ : st) {
    boxgrid.build(boxes, kept);
    pairs = 0;
    for (int64_t c = 0; c < boxgrid.cells(); ++c)
      boxgrid.each_pair_in(c, [&](int32_t, int32_t) { ++pairs; });
    benchmark::DoNotOptimize(pairs);
  }
  st.counters["pairs"] = static_cast<double>(pairs);
  st.SetItemsProcessed(st.iterations() * static_cast<int64_t>(boxes.size()));
}
BENCHMARK(EdgeBoxPairs)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);

// The crossing search behind the stats' self_intersections and self-collision's fail-safe,
// count_self_intersections, on an N×N cloth flat (arg 0; where no side of a neighbour's plane
// can be told, the costliest pairs) and draped over a sphere by 30 frames of xpbd (arg 1), on
// the threads OpenMP is given. Counts the crossing pairs.
void CrossingSearch(benchmark::State& st) {
  Simulation sim(over_sphere(static_cast<int>(st.range(0)), 0.7));
  if (st.range(1) == 1)
    for (int f = 0; f < 30; ++f) sim.step();
  int64_t crossings = 0;
  for (auto _ : st) {
    crossings = count_self_intersections(sim.model().triangles, sim.state().x);
    benchmark::DoNotOptimize(crossings);
  }
  st.counters["crossings"] = static_cast<double>(crossings);
  st.SetItemsProcessed(st.iterations() * static_cast<int64_t>(sim.model().triangles.size()));
}
BENCHMARK(CrossingSearch)
    ->Args({128, 0})
    ->Args({128, 1})
    ->Args({256, 0})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace drape
