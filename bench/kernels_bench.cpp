// Micro-benchmarks of the per-substep kernels on an N×N hanging cloth:
//   build/bench/drape_kernels --benchmark_filter=Springs
#include <benchmark/benchmark.h>

#include "drape/simulation.h"
#include "forces.h"

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
  def.colliders.push_back({ColliderType::plane, Vec3(0, 1.0, 0), 0, Vec3::UnitY(), 0.3, 0.01});
  Simulation sim(def);
  ClothState state = sim.state();
  for (auto _ : st) {
    resolve_contacts(sim.colliders(), state);
    benchmark::DoNotOptimize(state.x.data());
  }
  st.SetItemsProcessed(st.iterations() * sim.model().size());
}
BENCHMARK(Contacts)->Arg(32)->Arg(128)->Arg(256);

void Frame(benchmark::State& st) {
  Simulation sim(grid(static_cast<int>(st.range(0))));
  for (auto _ : st) sim.step();
  st.SetItemsProcessed(st.iterations() * sim.model().size());
}
BENCHMARK(Frame)->Arg(32)->Arg(128);

}  // namespace
}  // namespace drape
