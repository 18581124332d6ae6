// `drape run SCENE`: simulate headless, print a summary, write stats and mesh exports.
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/commands.h"
#include "app/exports.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/atomic_file.h"
#include "io/scene_io.h"

namespace drape::app {

namespace {

struct RunOptions {
  std::string scene;
  std::optional<double> seconds;
  std::vector<std::string> sets;
  std::string stats;
  std::string export_path;
  std::string format;  // empty: from --export's name
  int every = 1;
  int threads = 0;
  bool quiet = false;
  bool force = false;
};

int run(const RunOptions& o) {
#ifdef _OPENMP
  if (o.threads > 0) omp_set_num_threads(o.threads);
#endif
  std::vector<std::string> sets = o.sets;
  if (o.seconds) sets.push_back("duration=" + std::to_string(*o.seconds));

  using clock = std::chrono::steady_clock;
  std::optional<Simulation> sim;
  int64_t frames = 0;
  double setup_ms = 0.0;
  ExportTarget target;
  try {
    const SceneDef def = io::load_scene(o.scene, sets);
    frames = frame_count(def);
    const auto t0 = clock::now();
    try {
      if (!o.force) check_memory(def);
      sim.emplace(def);
      if (!o.force) check_work(*sim, frames);
    } catch (const InputError& e) {
      throw InputError(o.scene + ": " + e.path(), e.problem());
    }
    setup_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
    if (!o.export_path.empty()) {
      target = resolve_export(o.export_path, o.format, o.scene, o.every);
      prepare_export(target, *sim, frames, o.force);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }

  std::optional<Exporter> exporter;
  RunHooks hooks;
  if (!o.quiet) hooks.progress_label = sim->def().name;
  if (!o.export_path.empty()) {
    exporter.emplace(target, frames, "drape " DRAPE_VERSION);
    hooks.after_frame = [&](const Simulation& s) { exporter->after_frame(s); };
  }
  install_interrupt_handlers();
  RunResult result;
  try {
    result = run_frames(*sim, frames, hooks);
    // A stopped run still exports where it stopped; caches are completed here.
    if (exporter) exporter->finish(*sim, result);
  } catch (const std::exception& e) {  // an export that cannot be written
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return 1;
  }
  result.setup_ms = setup_ms;

  const nlohmann::json stats = stats_json(*sim, result);
  if (!o.stats.empty()) {
    try {
      io::write_file_atomically(o.stats, stats.dump(2) + "\n");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "drape: error: %s\n", e.what());
      return 1;
    }
  }

  const Diagnostics d = sim->diagnostics();
  if (!o.quiet) {
    std::printf(
        "%s: %lld frames (%.2f s simulated) in %.2f s, %.3f ms/frame (median), %d substeps/frame, "
        "method %s\n"
        "  %d particles, %zu springs; kinetic energy %.3g J, strain max %.2f%% mean %.2f%%, "
        "penetration %.3g m, pin drift %.3g m\n",
        sim->def().name.c_str(), static_cast<long long>(result.frames), sim->time(),
        result.wall_seconds, result.median_ms(), sim->substeps_per_frame(),
        method_text(*sim).c_str(), sim->model().size(), sim->model().springs.size(),
        d.kinetic_energy, 100.0 * d.max_strain, 100.0 * d.mean_strain, d.max_penetration,
        d.pinned_drift);
    if (exporter) std::printf("  exported %s\n", exporter->summary().c_str());
    if (!o.stats.empty()) std::printf("  stats written to %s\n", o.stats.c_str());
  }
  return exit_code(o.scene, *sim, result, "stats and exports so far are kept");
}

}  // namespace

std::function<int()> add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scene headless and report what happened");
  cmd->add_option("scene", o->scene, "Scene file (JSON)")->required();
  cmd->add_option("--seconds", o->seconds, "Simulated duration in s (overrides the scene's)");
  cmd->add_option("--set", o->sets, "Override a scene key: KEY=VALUE, e.g. cloth.mass=2")
      ->take_all()
      ->allow_extra_args(false);
  cmd->add_option("--stats", o->stats, "Write run statistics as JSON to this file");
  cmd->add_option("--export", o->export_path,
                  "Write one mesh per exported frame to this folder, or one animation cache of "
                  "the run to this FILE.pc2 or FILE.glb");
  cmd->add_option("--format", o->format,
                  "Export format: obj or ply (files per frame), pc2 or glb (one cache; with a "
                  "folder, named after the scene file). Default: from --export's name, else obj")
      ->check(CLI::IsMember({"obj", "ply", "pc2", "glb"}));
  cmd->add_option("--every", o->every, "Export every Nth frame (and always the last)")
      ->check(CLI::Range(1, 1 << 30));
  cmd->add_option("--threads", o->threads, "Threads to use (default: all cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
  cmd->add_flag("--force", o->force,
                "Run beyond the memory and work budgets, and export into a folder that holds an "
                "earlier run's frames");
  return [cmd, o] { return cmd->parsed() ? run(*o) : -1; };
}

}  // namespace drape::app
