#include "app/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "app/commands.h"
#include "app/terminal.h"
#include "drape/error.h"

namespace drape::app {

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::ok: return "ok";
    case RunStatus::diverged: return "diverged";
    case RunStatus::interrupted: return "interrupted";
  }
  return "?";
}

double RunResult::median_ms() const {
  if (frame_ms.empty()) return 0.0;
  std::vector<double> sorted = frame_ms;
  const size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + mid, sorted.end());
  if (sorted.size() % 2 == 1) return sorted[mid];
  const double upper = sorted[mid];
  return 0.5 * (upper + *std::max_element(sorted.begin(), sorted.begin() + mid));
}

RunResult run_frames(Simulation& sim, int64_t frames, const RunHooks& hooks) {
  using clock = std::chrono::steady_clock;
  RunResult r;
  r.frame_ms.reserve(static_cast<size_t>(std::min<int64_t>(frames, 1 << 20)));
  Progress bar(hooks.progress_label, frames, !hooks.progress_label.empty());
  const auto start = clock::now();
  if (hooks.after_frame) hooks.after_frame(sim);
  for (int64_t f = 0; f < frames; ++f) {
    const auto t0 = clock::now();
    const bool ok = sim.step();
    r.frame_ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
    ++r.frames;
    if (!ok) {
      r.status = RunStatus::diverged;
      break;
    }
    if (hooks.after_frame) hooks.after_frame(sim);
    if (int s = interrupt_signal()) {
      r.status = RunStatus::interrupted;
      r.signal = s;
      break;
    }
    if (!hooks.progress_label.empty()) {
      char detail[96];
      const double elapsed = std::chrono::duration<double>(clock::now() - start).count();
      std::snprintf(detail, sizeof detail, "%lld/%lld frames  %.2f s sim  %.1f frames/s",
                    static_cast<long long>(f + 1), static_cast<long long>(frames), sim.time(),
                    elapsed > 0 ? (f + 1) / elapsed : 0.0);
      bar.update(f + 1, detail);
    }
  }
  bar.finish();
  r.wall_seconds = std::chrono::duration<double>(clock::now() - start).count();
  return r;
}

void check_memory(const SceneDef& def, const Budget& budget) {
  const int64_t particles = particle_count(def.cloth);
  const int64_t bytes = estimated_memory(def);
  if (bytes <= budget.bytes) return;
  const bool mesh = def.cloth.mesh != nullptr;
  char problem[320];
  std::snprintf(problem, sizeof problem,
                "%s%lld particles, about %.1f GiB, more than the %.1f GiB budget; %s, or pass "
                "--force to run it anyway",
                mesh ? "the mesh has "
                     : (std::to_string(def.cloth.cols) + "x" + std::to_string(def.cloth.rows) +
                        " is ")
                           .c_str(),
                static_cast<long long>(particles), static_cast<double>(bytes) / (1 << 30),
                static_cast<double>(budget.bytes) / (1 << 30),
                mesh ? "use a coarser mesh" : "lower the resolution");
  throw InputError(mesh ? "cloth.mesh" : "cloth.resolution", problem);
}

void check_work(const Simulation& sim, int64_t frames, const Budget& budget) {
  const double updates = static_cast<double>(frames) * sim.substeps_per_frame() *
                         static_cast<double>(sim.model().size() + sim.model().springs.size());
  if (updates <= budget.updates) return;
  char problem[320];
  std::snprintf(problem, sizeof problem,
                "%lld frames of %d substeps over %d particles and %zu springs is %.3g updates, "
                "hours of work (the budget is %.3g); shorten the duration, raise solver.dt, "
                "or pass --force to run it anyway",
                static_cast<long long>(frames), sim.substeps_per_frame(), sim.model().size(),
                sim.model().springs.size(), updates, budget.updates);
  throw InputError("duration", problem);
}

int exit_code(const std::string& scene, const Simulation& sim, const RunResult& run,
              const char* kept) {
  if (sim.diverged()) {
    std::fprintf(stderr, "drape: error: %s: diverged at frame %lld (t = %.4g s): %s\n",
                 scene.c_str(), static_cast<long long>(sim.diverged_frame()), sim.time(),
                 sim.divergence().c_str());
    return kExitDiverged;
  }
  if (run.status == RunStatus::interrupted) {
    std::fprintf(stderr, "drape: interrupted at frame %lld; %s\n",
                 static_cast<long long>(sim.frame()), kept);
    return interrupt_exit_code(run.signal);
  }
  return kExitOk;
}

nlohmann::json stats_json(const Simulation& sim, const RunResult& run) {
  const Diagnostics d = sim.diagnostics();
  nlohmann::json j;
  j["scene"] = sim.def().name;
  j["status"] = to_string(run.status);
  j["diverged_frame"] = sim.diverged() ? nlohmann::json(sim.diverged_frame()) : nullptr;
  j["message"] = sim.diverged() ? nlohmann::json(sim.divergence()) : nullptr;
  j["method"] = to_string(sim.def().solver.method);
  j["particles"] = sim.model().size();
  j["springs"] = sim.model().springs.size();
  j["frames"] = run.frames;
  j["substeps_per_frame"] = sim.substeps_per_frame();
  j["dt"] = sim.def().solver.dt;
  j["sim_seconds"] = sim.time();
  j["wall_seconds"] = run.wall_seconds;
  j["setup_ms"] = run.setup_ms;
  j["ms_per_frame"] = run.median_ms();
  const MemoryUse memory = sim.memory();
  j["state_bytes"] = memory.state;
  j["model_bytes"] = memory.model;
  j["workspace_bytes"] = memory.workspace;
  j["bytes_per_particle"] = memory.per_particle(sim.model().size());
  // JSON has no NaN or infinity: non-finite figures of a diverged state are written as null.
  auto figure = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  j["kinetic_energy"] = figure(d.kinetic_energy);
  j["max_strain"] = figure(d.max_strain);
  j["mean_strain"] = figure(d.mean_strain);
  j["max_penetration"] = figure(d.max_penetration);
  j["pinned_drift"] = figure(d.pinned_drift);
  j["finite"] = d.finite;
  return j;
}

}  // namespace drape::app
