#include "io/run_stats.h"

#include <algorithm>
#include <cmath>

#include "drape/self_intersections.h"

namespace drape::io {

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::ok:
      return "ok";
    case RunStatus::diverged:
      return "diverged";
    case RunStatus::interrupted:
      return "interrupted";
    case RunStatus::output_failed:
      return "output_failed";
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

nlohmann::json figure(double x) {
  if (std::isfinite(x)) return x;
  return std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf";
}

std::string json_text(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

nlohmann::json stats_json(const Simulation& sim, const RunResult& run) {
  const Diagnostics d = sim.diagnostics();
  nlohmann::json j;
  j["scene"] = sim.def().name;
  j["status"] = to_string(run.status);
  j["diverged_frame"] = sim.diverged() ? nlohmann::json(sim.diverged_frame()) : nullptr;
  j["message"] = sim.diverged()                           ? nlohmann::json(sim.divergence())
                 : run.status == RunStatus::output_failed ? nlohmann::json(run.output_error)
                                                          : nullptr;
  j["method"] = to_string(sim.def().solver.method);
  // What auto chose, as it ended, and how often it changed its effort; null for other methods.
  if (const AutoChoice* a = sim.auto_choice()) {
    j["auto"] = {{"method", to_string(a->method)},       {"precision", to_string(a->precision)},
                 {"substeps", a->substeps},              {"line_passes", a->line_passes},
                 {"stiff_sweeps", a->stiff_sweeps},      {"raises", a->raises},
                 {"lowers", a->lowers},                  {"out_of_reach", a->out_of_reach}};
  } else {
    j["auto"] = nullptr;
  }
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
  j["kinetic_energy"] = figure(d.kinetic_energy);
  j["max_strain"] = figure(d.max_strain);
  j["mean_strain"] = figure(d.mean_strain);
  j["max_penetration"] = figure(d.max_penetration);
  j["pinned_drift"] = figure(d.pinned_drift);
  j["finite"] = d.finite;
  // Not among the diagnostics, which are cheap enough for every frame: this one is not.
  j["self_intersections"] = count_self_intersections(sim.model().triangles, sim.state().x);
  return j;
}

}  // namespace drape::io
