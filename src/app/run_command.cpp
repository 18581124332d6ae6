// `drape run SCENE`: simulate headless, print a summary, write stats and mesh exports.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "app/commands.h"
#include "app/runner.h"
#include "app/terminal.h"
#include "drape/error.h"
#include "io/atomic_file.h"
#include "io/mesh_export.h"
#include "io/scene_io.h"

namespace drape::app {

namespace fs = std::filesystem;

namespace {

struct RunOptions {
  std::string scene;
  std::optional<double> seconds;
  std::vector<std::string> sets;
  std::string stats;
  std::string export_dir;
  std::string format = "obj";
  int every = 1;
  int threads = 0;
  bool quiet = false;
  bool force = false;
};

// An export folder holding frames of an earlier run is refused, so runs never mix.
void prepare_export_dir(const std::string& dir, bool force) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError("--export " + dir, "exists and is not a folder");
  if (fs::exists(dir, ec)) {
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      if (entry.path().filename().string().rfind("frame_", 0) == 0 && !force)
        throw InputError("--export " + dir,
                         "already holds frames of an earlier run; choose another folder or "
                         "pass --force to overwrite");
    }
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError("--export " + dir, "cannot create the folder: " + ec.message());
}

std::string frame_file(const std::string& dir, int64_t frame, const std::string& ext) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%05lld.%s", static_cast<long long>(frame), ext.c_str());
  return (fs::path(dir) / name).string();
}

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
    if (!o.export_dir.empty()) prepare_export_dir(o.export_dir, o.force);
  } catch (const InputError& e) {
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return kExitBadInput;
  }

  const io::MeshFormat format = o.format == "ply" ? io::MeshFormat::ply : io::MeshFormat::obj;
  int64_t exported = 0;
  RunHooks hooks;
  if (!o.quiet) hooks.progress_label = sim->def().name;
  if (!o.export_dir.empty()) {
    hooks.after_frame = [&](const Simulation& s) {
      if (s.frame() % o.every == 0 || s.frame() == frames) {
        io::write_mesh(frame_file(o.export_dir, s.frame(), o.format), format, s.model(),
                       s.state());
        ++exported;
      }
    };
  }
  install_interrupt_handlers();
  RunResult result;
  try {
    result = run_frames(*sim, frames, hooks);
  } catch (const std::exception& e) {  // an export that cannot be written
    std::fprintf(stderr, "drape: error: %s\n", e.what());
    return 1;
  }
  result.setup_ms = setup_ms;
  // A stopped run still exports where it stopped, so the last file is the last state.
  if (!o.export_dir.empty() && result.status != RunStatus::ok && !sim->diverged() &&
      sim->frame() % o.every != 0) {
    io::write_mesh(frame_file(o.export_dir, sim->frame(), o.format), format, sim->model(),
                   sim->state());
    ++exported;
  }

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
        to_string(sim->def().solver.method), sim->model().size(), sim->model().springs.size(),
        d.kinetic_energy, 100.0 * d.max_strain, 100.0 * d.mean_strain, d.max_penetration,
        d.pinned_drift);
    if (exported > 0)
      std::printf("  exported %lld %s files to %s\n", static_cast<long long>(exported),
                  o.format.c_str(), o.export_dir.c_str());
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
  cmd->add_option("--export", o->export_dir, "Write one mesh per exported frame to this folder");
  cmd->add_option("--format", o->format, "Export format")->check(CLI::IsMember({"obj", "ply"}));
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
